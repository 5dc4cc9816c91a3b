#!/bin/bash
# run.sh TAG [ENV=V ...]: the h = 0.01 pile, seeds 1-5, two at a time
TAG=$1; shift
for s in 1 2 3 4 5; do
  env "$@" /work/main/build/rbpart simulate --threads 1 --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s --stats ${TAG}_$s.csv -q &
  if (( s % 2 == 0 )); then wait; fi
done; wait
