"""Per replay set: the coupled solver's unsettled islands, and the relaxation's factorisations to
its own residual 1e-9 (ccp.py's output files as arguments)."""
import re
import statistics
import sys
from collections import defaultdict

rows = defaultdict(list)
for name in sys.argv[1:]:
    for line in open(name):
        t = line.split()
        if len(t) < 12 or t[3] != 'solver':
            continue
        scene = re.sub(r'_\d+\.txt$', '', t[0].split('/')[-1])
        rows[scene].append(dict(n=int(t[1]), settled=t[4] == '1', fact=int(t[5]), res=float(t[6]),
                                ccp=None if t[8] in ('None', 'failed') else int(t[8]), ccp_res=t[9],
                                coupled=float(t[11]), lift=float(t[13]) if len(t) > 13 else float('nan')))
print('| replay set | islands | coupled solver: unsettled | relaxation: unsettled | its factorisations, median / 90th pct / max | a loaded contact lifting, relaxation: islands with > 1 mm/s; most (m/s) | on the coupled solver\'s unsettled islands: the relaxation\'s factorisations (max); its answer\'s coupled residual, median (max), against the solver\'s |')
print('|---|---:|---:|---:|---|---|---|')
order = ['box_pile_h60', 'box_pile_h100', 'chain_drop', 'rock_pile', 'large_rock_pile']
for scene in [s for s in order if s in rows] + [s for s in rows if s not in order]:
    v = rows[scene]
    f = sorted(x['ccp'] for x in v if x['ccp'] is not None)
    uns = [x for x in v if not x['settled']]
    p90 = f[int(0.9 * (len(f) - 1))] if f else None
    line = f"| {scene} | {len(v)} | {len(uns)} | {sum(x['ccp'] is None for x in v)} | {statistics.median(f)} / {p90} / {max(f)} |"
    line += f" {sum(x['lift'] > 1e-3 for x in v)}; {max(x['lift'] for x in v):.2g} |"
    if uns:
        uf = [x['ccp'] for x in uns if x['ccp'] is not None]
        line += (f" {max(uf) if uf else '-'}; {statistics.median(x['coupled'] for x in uns):.2g} "
                 f"({max(x['coupled'] for x in uns):.2g}) against {statistics.median(x['res'] for x in uns):.2g} "
                 f"({max(x['res'] for x in uns):.2g}) |")
    else:
        line += ' - |'
    print(line)
