#!/usr/bin/python3
# One line per whole run (rbpart simulate --stats CSVs named TAG_SCENESEED.csv in DIR): scene, seed,
# build, steps above 1e-9, total solve, median of the last 100 steps, median factorisations of the
# last 100 steps, kinetic energy at the end, deepest penetration. Then, per scene, the medians of
# both builds, a Mann-Whitney test on the unsettled counts and the runs that end above 1 J.
# Usage: runs.py DIR BEFORE AFTER > runs.tsv
import csv, glob, re, statistics as st, sys
from scipy.stats import mannwhitneyu
d, tags = sys.argv[1], sys.argv[2:4]
runs = {}
print('scene\tseed\tbuild\tunsettled\tsolve_s\tlast100_median_ms\tlast100_factorizations\tke_end_J\tmax_penetration_mm')
for f in sorted(glob.glob(d + '/*.csv')):
    m = re.match(r'(\w+?)_([a-z]+)(\d+)\.csv$', f.split('/')[-1])
    if not m or m.group(1) not in tags: continue
    tag, scene, seed = m.group(1), m.group(2), int(m.group(3))
    r = list(csv.DictReader(open(f)))
    last = r[-100:]
    row = (sum(int(x['unsettled']) > 0 for x in r), sum(float(x['solve_ms']) for x in r) / 1e3,
           st.median(float(x['solve_ms']) for x in last), st.median(int(x['factorizations']) for x in last),
           float(r[-1]['kinetic_energy']), 1e3 * max(float(x['max_penetration']) for x in r))
    runs.setdefault(scene, {}).setdefault(tag, []).append(row)
    print(f'{scene}\t{seed}\t{tag}\t{row[0]}\t{row[1]:.2f}\t{row[2]:.2f}\t{row[3]:g}\t{row[4]:.2e}\t{row[5]:.1f}')
for scene, by in sorted(runs.items()):
    if not all(t in by for t in tags): continue
    a, b = ([x[0] for x in by[t]] for t in tags)
    line = [f'# {scene}: {len(a)} seeds']
    for t in tags:
        L = by[t]
        line.append(f'{t}: unsettled {st.median(x[0] for x in L):g} ({min(x[0] for x in L)}-{max(x[0] for x in L)}), '
                    f'solve {st.median(x[1] for x in L):.1f} s, last 100 {st.median(x[2] for x in L):.1f} ms, '
                    f'above 1 J at the end {sum(x[4] > 1 for x in L)}')
    line.append(f'Mann-Whitney p = {mannwhitneyu(a, b).pvalue:.2f}')
    print('; '.join(line))
