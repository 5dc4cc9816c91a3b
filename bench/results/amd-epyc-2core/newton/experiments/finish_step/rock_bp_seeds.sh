#!/bin/bash
BIN=$1; OUT=$2; SEEDS="$3"; mkdir -p "$OUT"
for s in $SEEDS; do
  for v in $VARIANTS; do
    tag=${v%%:*}; e=${v#*:}
    [ $s -le 13 ] && { [ -f "$OUT/${tag}_rock_$s.csv" ] || env $e timeout 600 $BIN simulate --threads 1 --scene rock_pile --set seed=$s --stats "$OUT/${tag}_rock_$s.csv" -q > /dev/null 2>&1; }
    [ -f "$OUT/${tag}_bp_$s.csv" ] || env $e timeout 600 $BIN simulate --threads 1 --scene box_pile --set mass_ratio_set=1 --set seed=$s --stats "$OUT/${tag}_bp_$s.csv" -q > /dev/null 2>&1
  done
  echo "done $s $(date +%T)" >> $OUT/progress3.txt
done
