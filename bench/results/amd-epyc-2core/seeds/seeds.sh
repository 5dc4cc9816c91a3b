#!/bin/bash
# The solver's seeded scenes over seeds 1-5 (Large Rock Pile 1-3), one solver thread, two runs at a
# time: stats into OUT/TAG_SCENE_SEED.csv; summary.py OUT TAG... prints median and range per scene.
# Usage: seeds.sh RBPART TAG OUT   (e.g. seeds.sh build/rbpart cur /tmp/seeds)
BIN=$1; TAG=$2; OUT=$3; mkdir -p "$OUT"
jobs=()
add() { jobs+=("$*"); }
# The longest runs first, so that the estimate of the time left errs long.
for s in 1 2 3; do add large $s --scene large_rock_pile --set seed=$s; done
for s in 1 2 3 4 5; do
  add rock $s --scene rock_pile --set seed=$s
  add bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s
  add hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s
done
total=${#jobs[@]}; done_=0; start=$(date +%s)
for ((i = 0; i < total; i += 2)); do
  for ((k = i; k < i + 2 && k < total; ++k)); do
    set -- ${jobs[$k]}; name=$1; seed=$2; shift 2
    "$BIN" simulate --threads 1 "$@" --stats "$OUT/${TAG}_${name}_$seed.csv" -q &
  done
  wait
  done_=$((k)); now=$(date +%s)
  echo "$TAG: $done_ of $total runs, about $(( (now - start) * (total - done_) / done_ )) s left" >&2
done
