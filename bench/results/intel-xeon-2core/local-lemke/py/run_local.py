import numpy as np, time, sys
from big import *
K=int(sys.argv[2]) if len(sys.argv)>2 else 40
for name in sys.argv[1].split(','):
    P=loadbin(f'/tmp/s36/big/{name}.bin')
    lam=project(P,P['best'])
    f,w=fw(P,lam)
    print(name,P['n'],'best res %.3e'%np.max(np.abs(f)), 'rows >1e-9:',np.sum(np.abs(f)>1e-9),'>1e-6',np.sum(np.abs(f)>1e-6),flush=True)
    con=contact_of(P)
    st=state_of(P,lam,w)
    if len(sys.argv)>3: st=P['st'].copy(); print(' indicated state; differs from natural map on',np.sum(st!=state_of(P,lam,w)))
    for rnd in range(12):
        bad=np.where(np.abs(f)>1e-9)[0]
        order=bad[np.argsort(-np.abs(f[bad]))]
        cs=[]
        for j in order:
            if con[j] not in cs: cs.append(con[j])
            if len(cs)>=K: break
        T=[j for j in range(P['n']) if con[j] in set(cs)]
        t=time.time()
        new,it=local_solve(P,lam,st,T)
        if new is None: print(' round',rnd,'|T|',len(T),'lemke ray',it); break
        lam2=project(P,new); f2,w2=fw(P,lam2)
        print(' round',rnd,'|T|',len(T),'pivots',it,'res %.3e'%np.max(np.abs(f2)),'bad rows',np.sum(np.abs(f2)>1e-9),'unproj diff %.2e'%np.max(np.abs(new-lam2)),'%.1fs'%(time.time()-t),flush=True)
        lam,f,w=lam2,f2,w2
        if np.max(np.abs(f))<=1e-9: break
        st=state_of(P,lam,w)
