#!/bin/bash
# ab4.sh BASE NEW OUT: the two builds side by side (one run per core) on box pile h = 0.01 (seeds
# 1-12), h = 1/60 (1-10), Rock Pile (1-8), Chain Drop, Log Tower, Large Rock Pile (1-2):
# OUT/base_SCENE_SEED.csv and OUT/new_SCENE_SEED.csv.
BASE=$1; NEW=$2; OUT=$3; mkdir -p "$OUT"
jobs=()
for s in 1 2; do jobs+=("large $s --scene large_rock_pile --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8 9 10 11 12; do jobs+=("hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8 9 10; do jobs+=("bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8; do jobs+=("rock $s --scene rock_pile --set seed=$s"); done
jobs+=("chain 1 --scene chain_drop" "log 1 --scene log_tower")
total=${#jobs[@]}; n=0; start=$(date +%s)
for j in "${jobs[@]}"; do
  set -- $j; name=$1; seed=$2; shift 2
  "$BASE" simulate --threads 1 "$@" --stats "$OUT/base_${name}_$seed.csv" -q &
  "$NEW" simulate --threads 1 "$@" --stats "$OUT/new_${name}_$seed.csv" -q &
  wait
  n=$((n + 1)); now=$(date +%s)
  echo "$n of $total, about $(( (now - start) * (total - n) / n )) s left" >&2
done
