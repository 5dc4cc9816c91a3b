#!/bin/bash
# States at the end of the base build's runs (the resting fixtures).
B=/work/main/build/rbpart
jobs=()
for s in 1 2 3 4 5 6 7 8 9 10; do jobs+=("bp$s --scene box_pile --set mass_ratio_set=1 --set seed=$s --steps 300"); done
for s in 1 2 3 4 5 6 7 8 9 10 11 12; do jobs+=("hard$s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8; do jobs+=("rock$s --scene rock_pile --set seed=$s --steps 500"); done
n=${#jobs[@]}
for ((i=0;i<n;i+=2)); do
  for ((k=i;k<i+2&&k<n;k++)); do set -- ${jobs[$k]}; name=$1; shift; [ -f S_$name.json ] || $B simulate --threads 1 "$@" --state S_$name.json -q & done; wait
done
