import csv,sys,statistics as st
for f in sys.argv[1:]:
    r=list(csv.DictReader(open(f)))
    uns=sum(int(x['unsettled'])>0 for x in r)
    fac=[int(x['factorizations']) for x in r]
    last=r[-100:]
    print(f.split('/')[-1], 'steps',len(r),'unsettled',uns,'solve_s %.1f'%(sum(float(x['solve_ms']) for x in r)/1e3),
          'fact med/max',st.median(fac),max(fac),'fact_last100 med',st.median(int(x['factorizations']) for x in last),
          'KE %.2e'%float(r[-1]['kinetic_energy']),'pen %.1f mm'%(1e3*max(float(x['max_penetration']) for x in r)),
          'pen_end %.2f mm'%(1e3*float(r[-1]['max_penetration'])))
