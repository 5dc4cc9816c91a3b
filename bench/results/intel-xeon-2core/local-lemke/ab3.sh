#!/bin/bash
# ab3.sh OUT TAG BIN: box pile h = 0.01 (seeds 1-6), Rock Pile (1-5), box pile h = 1/60 (1-6), Chain
# Drop; one solver thread, two runs at a time: OUT/TAG_SCENE_SEED.csv; sum3.py OUT TAG,TAG... sums up.
OUT=$1; TAG=$2; BIN=$3; mkdir -p "$OUT"
jobs=()
for s in 1 2 3 4 5 6; do jobs+=("hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s"); done
for s in 1 2 3 4 5; do jobs+=("rock $s --scene rock_pile --set seed=$s"); done
for s in 1 2 3 4 5 6; do jobs+=("bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s"); done
jobs+=("chain 1 --scene chain_drop")
n=${#jobs[@]}
for ((i=0;i<n;i+=2)); do
  for ((k=i;k<i+2&&k<n;k++)); do
    set -- ${jobs[$k]}; name=$1; seed=$2; shift 2
    $BIN simulate --threads 1 "$@" --stats $OUT/${TAG}_${name}_$seed.csv -q &
  done
  wait
done
