#!/bin/bash
BIN=$1; OUT=$2; mkdir -p "$OUT"  # usage: VARIANTS="base:FLIP=0 f3:FLIP=3" jobs2.sh RBPART OUT
jobs=()
add() { jobs+=("$*"); }
for s in 6 7 8 9 10 11 12 13; do add rock $s --scene rock_pile --set seed=$s; done
for s in 6 7 8 9 10 11 12 13 14 15; do add bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s; done
for s in 6 7 8 9 10; do add hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s; done
for s in 3 4 5 6 7; do add large $s --scene large_rock_pile --set seed=$s; done
for j in "${jobs[@]}"; do
  set -- $j; name=$1; seed=$2; shift 2
  for v in $VARIANTS; do
    tag=${v%%:*}; e=${v#*:}
    [ -f "$OUT/${tag}_${name}_$seed.csv" ] || env $e timeout 600 $BIN simulate --threads 1 "$@" --stats "$OUT/${tag}_${name}_$seed.csv" -q > /dev/null 2>&1
  done
  echo "done $name $seed $(date +%T)" >> $OUT/progress.txt
done
