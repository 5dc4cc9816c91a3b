#!/bin/bash
BIN=$1; OUT=$2; SEEDS="$3"; mkdir -p "$OUT"
for s in $SEEDS; do
  for v in $VARIANTS; do
    tag=${v%%:*}; e=${v#*:}
    [ -f "$OUT/${tag}_rock_$s.csv" ] || env $e timeout 600 $BIN simulate --threads 1 --scene rock_pile --set seed=$s --stats "$OUT/${tag}_rock_$s.csv" -q > /dev/null 2>&1
  done
  echo "done $s $(date +%T)" >> $OUT/progress4.txt
done
