#!/bin/bash
B=/tmp/gap_rbpart
run() { name=$1; shift; GAP=1e-4 $B simulate --threads 1 "$@" --stats /tmp/gap/gap_$name.csv -q; }
for s in 1 2 3; do
  run rock$s --scene rock_pile --set seed=$s & run bp$s --scene box_pile --set mass_ratio_set=1 --set seed=$s; wait
  run hard$s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s
  echo done $s
done
