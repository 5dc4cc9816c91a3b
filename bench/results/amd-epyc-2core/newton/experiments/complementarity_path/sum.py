# Per scene and variant, over the runs of runs.sh in /tmp/pr: median unsettled steps, per-seed counts,
# runs above 1 J at the end, median solve (s), median and max factorisations per step. Usage: sum.py
import csv, glob, sys, statistics, collections
res=collections.defaultdict(list)
for f in sorted(glob.glob('/tmp/pr/*.csv')):
    name=f.split('/')[-1][:-4]; tag,sc,seed=name.rsplit('_',2)
    r=list(csv.DictReader(open(f)))
    if not r: continue
    u=sum(int(x['unsettled'])>0 for x in r); fa=sorted(int(x['factorizations']) for x in r)
    res[(sc,tag)].append((int(seed),u,len(r),float(r[-1]['kinetic_energy']),sum(float(x['solve_ms']) for x in r)/1000,fa[len(fa)//2],fa[-1]))
for k in sorted(res):
    v=sorted(res[k])
    print(k, 'median unsettled', statistics.median(x[1] for x in v), 'seeds', [(x[0],x[1]) for x in v], 'KE>1:', sum(x[3]>1 for x in v), 'solve med %.1f'%statistics.median(x[4] for x in v), 'fact med/max', statistics.median(x[5] for x in v), max(x[6] for x in v))
