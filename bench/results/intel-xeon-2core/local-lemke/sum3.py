# Summary of ab3.sh runs: per scene and tag, unsettled steps per seed and their median, total solve,
# median of the last 100 steps, median factorisations of the largest island at rest, slowest step,
# runs above 0.01 J at the end.  Usage: sum3.py OUT TAG,TAG,...
import csv,glob,sys,statistics as st
out=sys.argv[1]; tags=sys.argv[2].split(',')
for scene in ['hard','rock','bp','chain']:
    for tag in tags:
        us=[];ts=[];ke=[];l100=[];fmed=[];fmax=[]
        for f in sorted(glob.glob(f'{out}/{tag}_{scene}_*.csv')):
            r=list(csv.DictReader(open(f)))
            us.append(sum(1 for x in r if int(x['unsettled'])>0))
            ts.append(sum(float(x['solve_ms']) for x in r)/1000); ke.append(float(r[-1]['kinetic_energy']))
            l100.append(st.median(float(x['solve_ms']) for x in r[-100:]))
            fmed.append(st.median(int(x['island_factorizations']) for x in r[-100:])); fmax.append(max(float(x['solve_ms']) for x in r))
        if not us: continue
        print('%-5s %-6s unsettled %-28s med %5.1f | solve s %5.2f | last100 ms %5.2f | isl fact rest %4.1f | slowest ms %6.1f | KE>0.01 %d'%(scene,tag,us,st.median(us),st.median(ts),st.median(l100),st.median(fmed),st.median(fmax),sum(k>0.01 for k in ke)))
