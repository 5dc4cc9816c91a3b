"""Medians over seeds of base_* and prox_* runs in OUT (run.sh); p: two-sided Mann-Whitney on unsettled steps.
Usage: ab_summary.py OUT"""
import csv, glob, collections, statistics, math
import sys; OUT=sys.argv[1]
data = collections.defaultdict(lambda: collections.defaultdict(dict))
for f in glob.glob(OUT + '/*.csv'):
    tag, scene, seed = f.split('/')[-1][:-4].split('_')
    r = list(csv.DictReader(open(f)))
    if not r: continue
    uns = sum(float(x['unsettled']) > 0 for x in r)
    solve = sum(float(x['solve_ms']) for x in r) / 1000
    fa = [float(x['factorizations']) for x in r]
    sm = [float(x['solve_ms']) for x in r]
    ke = float(r[-1]['kinetic_energy'])
    pen = max(float(x.get('max_penetration', x.get('penetration', 0)) or 0) for x in r) if ('max_penetration' in r[0] or 'penetration' in r[0]) else float('nan')
    data[scene][tag][int(seed)] = (uns, solve, statistics.median(fa[-100:]), ke, statistics.median(sm[-100:]), pen)
def mwu_p(a, b):
    n1, n2 = len(a), len(b); allv = sorted((v, i) for i, v in enumerate(a + b))
    ranks = [0] * (n1 + n2); i = 0
    while i < len(allv):
        j = i
        while j + 1 < len(allv) and allv[j + 1][0] == allv[i][0]: j += 1
        for k in range(i, j + 1): ranks[allv[k][1]] = (i + j) / 2 + 1
        i = j + 1
    u = sum(ranks[:n1]) - n1 * (n1 + 1) / 2
    mu = n1 * n2 / 2; sd = math.sqrt(n1 * n2 * (n1 + n2 + 1) / 12)
    if sd == 0: return 1.0
    z = (abs(u - mu) - 0.5) / sd
    return math.erfc(z / math.sqrt(2))
for scene in sorted(data):
    a, b = data[scene].get('base', {}), data[scene].get('prox', {})
    seeds = sorted(set(a) & set(b))
    if not seeds: continue
    col = lambda d, k: [d[s][k] for s in seeds]
    med = statistics.median
    print(f"{scene:6s} n={len(seeds):2d} unsettled {med(col(a,0)):6.1f} -> {med(col(b,0)):6.1f} (p={mwu_p(col(a,0), col(b,0)):.2f})  fact-last100 {med(col(a,2)):5.1f} -> {med(col(b,2)):5.1f}  solve {med(col(a,1)):5.1f} -> {med(col(b,1)):5.1f} s  last100 ms {med(col(a,4)):5.1f} -> {med(col(b,4)):5.1f} (<=10ms {sum(x<=10 for x in col(a,4))} -> {sum(x<=10 for x in col(b,4))})  thrown {sum(x>1 for x in col(a,3))} -> {sum(x>1 for x in col(b,3))}  KE {max(col(a,3)):.2g} -> {max(col(b,3)):.2g}  pen {max(col(a,5)):.2g} -> {max(col(b,5)):.2g}")
