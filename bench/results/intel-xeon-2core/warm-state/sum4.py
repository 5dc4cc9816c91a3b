# sum4.py OUT: base against new per scene: unsettled steps (median, per seed; exact two-sided
# Mann-Whitney p), total solve, median of the last 100 steps, the largest island's factorisations
# at rest (median of the last 100 steps), slowest step, runs above 0.01 J at the end.
import csv,glob,sys,statistics as st,itertools,random
def mw_p(a,b):
    allv=a+b; n=len(a)
    def U(x,y): return sum((xi>yi)+0.5*(xi==yi) for xi in x for yi in y)
    mean=len(a)*len(b)/2; d0=abs(U(a,b)-mean)
    combos=list(itertools.combinations(range(len(allv)),n)) if len(allv)<=20 else None
    if combos is None:
        rng=random.Random(1); combos=[tuple(sorted(rng.sample(range(len(allv)),n))) for _ in range(20000)]
    cnt=0
    for idx in combos:
        s=set(idx); x=[allv[i] for i in idx]; y=[allv[i] for i in range(len(allv)) if i not in s]
        cnt+=abs(U(x,y)-mean)>=d0-1e-12
    return cnt/len(combos)
out=sys.argv[1]
for scene in ['hard','bp','rock','large','chain','log']:
    res={}
    for tag in ['base','new']:
        files=sorted(glob.glob(f'{out}/{tag}_{scene}_*.csv'),key=lambda f:int(f.split('_')[-1][:-4]))
        d=dict(us=[],ts=[],l100=[],rest=[],slow=[],ke=[],fmax=[])
        for f in files:
            r=list(csv.DictReader(open(f)))
            d['us'].append(sum(1 for x in r if int(x['unsettled'])>0)); d['ts'].append(sum(float(x['solve_ms']) for x in r)/1000)
            d['l100'].append(st.median(float(x['solve_ms']) for x in r[-100:])); d['rest'].append(st.median(int(x['island_factorizations']) for x in r[-100:]))
            d['slow'].append(max(float(x['solve_ms']) for x in r)); d['ke'].append(float(r[-1]['kinetic_energy'])); d['fmax'].append(max(int(x['island_factorizations']) for x in r))
        res[tag]=d
    if not res['base']['us']: continue
    p=mw_p(res['base']['us'],res['new']['us']) if len(res['base']['us'])>1 else float('nan')
    for tag in ['base','new']:
        d=res[tag]
        print('%-5s %-4s unsettled %6.1f %-40s | solve %6.2f s | last100 %6.2f ms | rest fact %4.1f | slowest %7.1f ms | KE>0.01 %d%s'%(scene,tag,st.median(d['us']),str(d['us']),st.median(d['ts']),st.median(d['l100']),st.median(d['rest']),st.median(d['slow']),sum(k>0.01 for k in d['ke']),'' if tag=='base' else '  p=%.2f'%p))
