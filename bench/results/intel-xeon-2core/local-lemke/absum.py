# Summary of ab.sh runs: per scene and build, unsettled steps per seed, total solve, median of the last
# 100 steps, runs above 0.01 J at the end.  Usage: absum.py OUT
import csv,glob,sys,statistics as st
out=sys.argv[1]
for scene in ['hard','bp']:
    rows=[]
    for tag in ['base','lemke']:
        us=[];ts=[];ke=[];fm=[];l100=[];isl=[]
        for f in sorted(glob.glob(f'{out}/{tag}_{scene}_*.csv')):
            r=list(csv.DictReader(open(f)))
            us.append(sum(1 for x in r if int(x['unsettled'])>0)); isl.append(sum(int(x['unsettled']) for x in r))
            ts.append(sum(float(x['solve_ms']) for x in r)/1000); ke.append(float(r[-1]['kinetic_energy']))
            fm.append(max(int(x['island_factorizations']) for x in r))
            l100.append(st.median(float(x['solve_ms']) for x in r[-100:]))
        print(scene,tag,'n',len(us),'unsettled steps',us,'median',st.median(us),'islands',st.median(isl),'solve s median %.2f'%st.median(ts),'last100 ms %.2f'%st.median(l100),'KE>0.01:',sum(k>0.01 for k in ke))
