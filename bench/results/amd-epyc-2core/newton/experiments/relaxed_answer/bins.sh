#!/bin/bash
# The bins of 1, 100 and 10000 kg boxes, seeds 1-5, 300 steps, one solver thread: per seed the
# kinetic energy at the end, steps above 1e-9, boxes whose centre ends below the floor's top, deepest penetration, solve time and factorisations per step.
# Usage: bins.sh RBPART TAG [simulate options]   (from the repository's root; writes to /tmp/bins)
BIN=$1; TAG=$2; shift 2
OUT=/tmp/bins; mkdir -p $OUT
cp bench/results/amd-epyc-2core/newton/experiments/fixed_bound/bin_1_100_10000_seed1.json $OUT/seed1.json
for S in 2 3 4 5; do  # box_pile's masses 10, 100, 1000 kg mapped to 1, 100, 10000
  $BIN scenes --export box_pile --set mass_ratio_set=1 --set seed=$S | /usr/bin/python3 -c "
import json, sys
d = json.load(sys.stdin); m = {10: 1, 100: 100, 1000: 10000}
for b in d['bodies']:
    if 'mass' in b: b['mass'] = m[b['mass']]
d['name'] = 'bin_1_100_10000'; json.dump(d, open('$OUT/seed$S.json', 'w'))"
done
for S in 1 2 3 4 5; do
  $BIN simulate --threads 1 --scene $OUT/seed$S.json --stats $OUT/${TAG}_$S.csv --state $OUT/${TAG}_$S.state.json -q "$@"
  /usr/bin/python3 - $OUT/${TAG}_$S.csv $OUT/${TAG}_$S.state.json $TAG $S <<'PY'
import csv, json, sys
r = list(csv.DictReader(open(sys.argv[1]))); st = json.load(open(sys.argv[2]))
bodies = st['bodies'] if 'bodies' in st else st
below = sum(1 for b in bodies if b.get('name') != 'floor' and b['position'][2] < 0)
f = sorted(float(x['factorizations']) for x in r)
print(sys.argv[3], 'seed', sys.argv[4], 'KE %.3g' % float(r[-1]['kinetic_energy']),
      'unsettled', sum(float(x['unsettled']) > 0 for x in r), 'below floor', below,
      'maxpen %.1f mm' % (1000 * max(float(x['max_penetration']) for x in r)),
      'solve %.1f s' % (sum(float(x['solve_ms']) for x in r) / 1000), 'fact med %d max %d' % (f[len(f) // 2], f[-1]))
PY
done
