#!/bin/bash
# Seeds 6-10 of the two box piles and 4-7 of the Large Rock Pile, both arms, two runs at a time.
# BIN is a build with switch.patch applied: ENERGY set runs this change, unset the build before.
# Usage: BIN=... more_seeds.sh OUT   (then ../seeds/summary.py OUT cur energy)
OUT=$1; mkdir -p "$OUT"
run() {
  tag=$1; name=$2; seed=$3; shift 3
  if [ "$tag" = energy ]; then export ENERGY=1; else unset ENERGY; fi
  "$BIN" simulate --threads 1 "$@" --set seed=$seed --stats "$OUT/${tag}_${name}_$seed.csv" -q
}
for s in 6 7 8 9 10; do
  for tag in cur energy; do
    run $tag bp $s --scene box_pile --set mass_ratio_set=1 &
    run $tag hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500
    wait
  done
done
for s in 4 5 6 7; do
  run cur large $s --scene large_rock_pile &
  run energy large $s --scene large_rock_pile
  wait
done
