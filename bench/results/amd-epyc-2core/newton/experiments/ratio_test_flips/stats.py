import csv, glob, collections, statistics, sys
from scipy.stats import mannwhitneyu
A, B = sys.argv[1], sys.argv[2]  # usage: stats.py TAG_A TAG_B OUT
data = collections.defaultdict(lambda: collections.defaultdict(dict))
for f in glob.glob(sys.argv[3] + '/*.csv'):
    name = f.split('/')[-1][:-4]
    tag, scene, seed = name.split('_')
    r = list(csv.DictReader(open(f)))
    if len(r) == 0: continue
    uns = sum(float(x['unsettled']) > 0 for x in r)
    solve = sum(float(x['solve_ms']) for x in r) / 1000
    fa = [float(x['factorizations']) for x in r]
    ke = float(r[-1]['kinetic_energy'])
    data[scene][tag][int(seed)] = (uns, solve, statistics.median(fa[-100:]), ke, len(r))
for scene in sorted(data):
    a, b = data[scene].get(A, {}), data[scene].get(B, {})
    seeds = sorted(set(a) & set(b))
    if not seeds: continue
    ua = [a[s][0] for s in seeds]; ub = [b[s][0] for s in seeds]
    fa_ = [a[s][2] for s in seeds]; fb = [b[s][2] for s in seeds]
    sa = [a[s][1] for s in seeds]; sb = [b[s][1] for s in seeds]
    ta = sum(a[s][3] > 1 for s in seeds); tb = sum(b[s][3] > 1 for s in seeds)
    p = mannwhitneyu(ua, ub).pvalue if len(seeds) > 2 else float('nan')
    print(f'{scene:6s} n={len(seeds):2d} unsettled {statistics.median(ua):6.1f} -> {statistics.median(ub):6.1f} (p={p:.2f})  fact-last100 {statistics.median(fa_):5.1f} -> {statistics.median(fb):5.1f}  solve {statistics.median(sa):5.1f} -> {statistics.median(sb):5.1f} s  thrown {ta} -> {tb}')
