#!/bin/bash
# Alternating runs of base and new from the resting Large Rock Pile: medians of the stage times over steps 6-25.
for i in 1 2 3; do
  for v in base main; do
    B=/tmp/base/build/rbpart; [ $v = main ] && B=/work/main/build/rbpart
    for t in 1 2; do
      $B simulate --scene large_rock_pile --initial-state /tmp/s27/lrp300.json --steps 25 --threads $t --stats /tmp/s29/ab_${v}_${t}_$i.csv > /dev/null 2>&1
    done
  done
done
python3 - <<'PY'
import csv,statistics as st
for t in (1,2):
  for v in ('base','main'):
    out=[]
    for i in (1,2,3):
      r=list(csv.DictReader(open(f'/tmp/s29/ab_{v}_{t}_{i}.csv')))[5:]
      out.append(tuple(st.median(float(x[c]) for x in r) for c in ('assemble_ms','graph_ms','total_ms')))
    print(f"threads {t} {v}: assemble " + ' '.join(f"{o[0]:.2f}" for o in out) + "  graph " + ' '.join(f"{o[1]:.2f}" for o in out) + "  total " + ' '.join(f"{o[2]:.1f}" for o in out))
PY
