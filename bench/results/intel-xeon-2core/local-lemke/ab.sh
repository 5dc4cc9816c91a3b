#!/bin/bash
# ab.sh BASE NEW OUT: box piles h = 0.01 (seeds 1-8) and h = 1/60 (seeds 1-10), one solver thread,
# the two builds side by side (one run each per core): OUT/base_* and OUT/lemke_*; absum.py OUT.
BASE=$1; NEW=$2; OUT=$3; mkdir -p "$OUT"
jobs=()
for s in 1 2 3 4 5 6 7 8; do jobs+=("hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8 9 10; do jobs+=("bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s"); done
for j in "${jobs[@]}"; do
  set -- $j; name=$1; seed=$2; shift 2
  "$BASE" simulate --threads 1 "$@" --stats "$OUT/base_${name}_$seed.csv" -q &
  "$NEW" simulate --threads 1 "$@" --stats "$OUT/lemke_${name}_$seed.csv" -q &
  wait
done
