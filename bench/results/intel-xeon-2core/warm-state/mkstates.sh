#!/bin/bash
# mkstates.sh BIN: the resting fixtures, S_NAME.json in the current directory: the states at the
# end of BIN's runs of the h = 1/60 box pile (seeds 1-10, 300 steps), the h = 0.01 pile (1-12, 500
# steps) and the Rock Pile (1-8, 500 steps), one solver thread, two runs at a time.
B=$1
jobs=()
for s in 1 2 3 4 5 6 7 8 9 10; do jobs+=("bp$s --scene box_pile --set mass_ratio_set=1 --set seed=$s --steps 300"); done
for s in 1 2 3 4 5 6 7 8 9 10 11 12; do jobs+=("hard$s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s"); done
for s in 1 2 3 4 5 6 7 8; do jobs+=("rock$s --scene rock_pile --set seed=$s --steps 500"); done
n=${#jobs[@]}
for ((i=0;i<n;i+=2)); do
  for ((k=i;k<i+2&&k<n;k++)); do set -- ${jobs[$k]}; name=$1; shift; [ -f S_$name.json ] || $B simulate --threads 1 "$@" --state S_$name.json -q & done; wait
done
