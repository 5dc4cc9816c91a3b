#!/bin/bash
B=/tmp/lin_rbpart
run() { tag=$1; shift; name=$1; shift; if [ $tag = lin ]; then LIN=1 $B simulate --threads 1 "$@" --stats /tmp/lin/${tag}_$name.csv -q; else $B simulate --threads 1 "$@" --stats /tmp/lin/${tag}_$name.csv -q; fi; }
for s in 1 2 3; do
  run base rock$s --scene rock_pile --set seed=$s & run lin rock$s --scene rock_pile --set seed=$s; wait
  run base bp$s --scene box_pile --set mass_ratio_set=1 --set seed=$s & run lin bp$s --scene box_pile --set mass_ratio_set=1 --set seed=$s; wait
  run base hard$s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s & run lin hard$s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s; wait
  echo done $s
done
