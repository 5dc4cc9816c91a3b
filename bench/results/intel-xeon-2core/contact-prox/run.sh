#!/bin/bash
# A/B: base and prox builds side by side (one per core), one solver thread each.
# Usage: BIN_DIR=DIR run.sh [OUT], DIR holding rbpart_base and rbpart_prox (the two builds).
# Then: python3 ab_summary.py OUT; python3 bins_summary.py OUT. Chain Drop variants: chain_variants.sh.
OUT=${1:-/tmp/contact-prox}; mkdir -p $OUT/bins; jobs=()
add() { jobs+=("$*"); }
for s in 1 2; do add large $s --scene large_rock_pile --set seed=$s; done
for s in 1 2 3; do add r400 $s --scene rock_pile --set rocks=400 --set seed=$s; done
for s in $(seq 1 12); do add hard $s --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s; done
for s in $(seq 1 10); do add rock $s --scene rock_pile --set seed=$s; done
for s in $(seq 1 10); do add bp $s --scene box_pile --set mass_ratio_set=1 --set seed=$s; done
add chain 1 --scene chain_drop
add log 1 --scene log_tower
start=$(date +%s); n=${#jobs[@]}; i=0
for j in "${jobs[@]}"; do
  set -- $j; name=$1; seed=$2; shift 2
  for T in base prox; do $BIN_DIR/rbpart_$T simulate --threads 1 "$@" --stats "$OUT/${T}_${name}_$seed.csv" -q > /dev/null 2>&1 & done
  wait; i=$((i+1))
  echo "done $name $seed $(date +%T) ($i of $n, $(( ($(date +%s)-start) ))s)" >> $OUT/progress.txt
done
for S in $(seq 1 10); do
  $BIN_DIR/rbpart_base scenes --export box_pile --set mass_ratio_set=1 --set seed=$S | /usr/bin/python3 -c "
import json, sys
d = json.load(sys.stdin); m = {10: 1, 100: 100, 1000: 10000}
for b in d['bodies']:
    if 'mass' in b: b['mass'] = m[b['mass']]
d['name'] = 'bin_1_100_10000'; json.dump(d, open('$OUT/bins/seed$S.json', 'w'))"
  for T in base prox; do
    $BIN_DIR/rbpart_$T simulate --threads 1 --scene $OUT/bins/seed$S.json --stats $OUT/bins/${T}_$S.csv --state $OUT/bins/${T}_$S.state.json -q &
  done
  wait
  echo "done bins $S $(date +%T)" >> $OUT/progress.txt
done
echo ALLDONE >> $OUT/progress.txt
