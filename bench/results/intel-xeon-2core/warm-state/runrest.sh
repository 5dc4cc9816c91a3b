#!/bin/bash
# runrest.sh BIN TAG: 40 steps from every resting fixture S_*.json (mkstates.sh) in the current
# directory, one solver thread, two runs at a time: stats into R_TAG_NAME.csv.
BIN=$1; TAG=$2
args() { case $1 in bp*) echo "--scene box_pile --set mass_ratio_set=1 --set seed=${1#bp}";; hard*) echo "--scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --set seed=${1#hard}";; rock*) echo "--scene rock_pile --set seed=${1#rock}";; esac; }
names=(); for f in S_*.json; do n=${f#S_}; names+=("${n%.json}"); done
for ((i=0;i<${#names[@]};i+=2)); do
  for ((k=i;k<i+2&&k<${#names[@]};k++)); do n=${names[$k]}; $BIN simulate --threads 1 $(args $n) --initial-state S_$n.json --steps 40 --stats R_${TAG}_$n.csv -q & done; wait
done
