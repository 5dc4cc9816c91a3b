#!/bin/bash
# The bins of 1, 100 and 10000 kg boxes on seeds 6-13 (bins.sh of ../newton/experiments/relaxed_answer
# runs seeds 1-5), 300 steps, one solver thread, two runs at a time; per seed: kinetic energy at the
# end, boxes whose centre ends below the floor's top, deepest penetration, unsettled steps.
# Usage: bins_more.sh RBPART TAG OUT   (from the repository's root)
BIN=$1; TAG=$2; OUT=$3; mkdir -p "$OUT"
for S in $(seq 6 13); do
  $BIN scenes --export box_pile --set mass_ratio_set=1 --set seed=$S |
    /usr/bin/python3 -c "import json, sys
d = json.load(sys.stdin)
for b in d['bodies']:
    if 'mass' in b: b['mass'] = {10: 1, 100: 100, 1000: 10000}[b['mass']]
json.dump(d, open('$OUT/seed$S.json', 'w'))"
done
for S in 6 8 10 12; do
  for T in $S $((S + 1)); do
    $BIN simulate --threads 1 --scene "$OUT/seed$T.json" --stats "$OUT/${TAG}_$T.csv" --state "$OUT/${TAG}_$T.state.json" -q &
  done
  wait
done
/usr/bin/python3 - "$OUT" "$TAG" <<'PY'
import csv, json, sys
out, tag = sys.argv[1:]
for s in range(6, 14):
    r = list(csv.DictReader(open(f'{out}/{tag}_{s}.csv')))
    st = json.load(open(f'{out}/{tag}_{s}.state.json'))
    below = sum(1 for b in st['bodies'] if b.get('name') != 'floor' and b['position'][2] < 0)
    print(tag, 'seed', s, 'KE %.2g' % float(r[-1]['kinetic_energy']), 'below floor', below,
          'maxpen %.1f mm' % (1000 * max(float(x['max_penetration']) for x in r)),
          'unsettled', sum(float(x['unsettled']) > 0 for x in r))
PY
