#!/bin/bash
# Chain Drop and nine variants of it, base and prox side by side: chain_variants.sh BIN_DIR OUT
BIN_DIR=$1; OUT=$2; mkdir -p "$OUT"
for v in links=100 links=90 links=110 links=80 links=120 height=4.6 height=4.7 height=4.4 end_ratio=50 end_ratio=200; do
  for T in base prox; do
    "$BIN_DIR/rbpart_$T" simulate --threads 1 --scene chain_drop --set $v --stats "$OUT/${T}_chain_${v/=/-}.csv" -q &
  done
  wait
done
