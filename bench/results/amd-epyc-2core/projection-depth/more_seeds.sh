#!/bin/bash
# The h = 0.01 box pile on seeds 6-15, 500 steps, one solver thread, two runs at a time; then per
# seed: kinetic energy at the end, deepest penetration, steps starting deeper than 2 mm, unsettled.
# Usage: more_seeds.sh RBPART TAG OUT   (from the repository's root)
BIN=$1; TAG=$2; OUT=$3; mkdir -p "$OUT"
for s in 6 8 10 12 14; do
  for t in $s $((s + 1)); do
    $BIN simulate --threads 1 --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 \
      --set seed=$t --stats "$OUT/${TAG}_hard_$t.csv" -q &
  done
  wait
done
/usr/bin/python3 - "$OUT" "$TAG" <<'PY'
import csv, sys
out, tag = sys.argv[1:]
rows = []
for s in range(6, 16):
    r = list(csv.DictReader(open(f'{out}/{tag}_hard_{s}.csv')))
    rows.append((float(r[-1]['kinetic_energy']), 1000 * max(float(x['max_penetration']) for x in r),
                 sum(float(x['max_penetration']) > 0.0020001 for x in r), sum(float(x['unsettled']) > 0 for x in r),
                 sum(float(x['project_ms']) for x in r) / 1000))
print(tag, 'KE at the end J ', ' '.join('%.1e' % o[0] for o in rows))
print(tag, 'deepest mm      ', ' '.join('%.1f' % o[1] for o in rows))
print(tag, 'steps > 2 mm    ', ' '.join('%d' % o[2] for o in rows), ' project s %.2f' % sum(o[4] for o in rows))
print(tag, 'unsettled steps ', ' '.join('%d' % o[3] for o in rows))
PY
