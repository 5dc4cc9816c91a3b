import sys, numpy as np, glob
import os
sys.path.insert(0,os.path.join(os.path.dirname(os.path.abspath(__file__)),'../../intel-xeon-2core/local-lemke/py'))
from isl import load, residual, lemke_lex, lemke_rev
# Fixed point of convex QPs (Cadoux / Acary et al.): min 1/2 l'Al + (q+s)'l s.t. l_n>=0, |l_t|<=mu l_n,
# s_n = sum_t mu_t |w_t| over the normal's friction rows, w = A l + q.
def constraints(P):
    n=P['n']; G=[]
    for j in range(n):
        k=P['nof'][j]
        if k<0:
            assert P['lo'][j]==0 and np.isinf(P['hi'][j])
            e=np.zeros(n); e[j]=1; G.append(e)
        else:
            for sg in (1,-1):
                e=np.zeros(n); e[k]=P['mu'][j]; e[j]=-sg; G.append(e)
    return np.array(G)
def qp(P,G,Ainv,qq):
    M=G@Ainv@G.T; c=-G@Ainv@qq
    z,it=lemke_lex(M,c)
    if z is None: return None,it
    return Ainv@(G.T@z-qq),it
for f in sorted(glob.glob(os.path.join(sys.argv[1],'island_*.txt')),key=lambda p:int(p.split('_')[-1][:-4])):
    P=load(f); n=P['n']; A=P['A']; q=P['q']; G=constraints(P); Ainv=np.linalg.inv(A)
    s=np.zeros(n); hist=[]; piv=0
    for it in range(60):
        lam,p=qp(P,G,Ainv,q+s); piv+=p
        if lam is None: hist.append('fail'); break
        r=residual(P,lam); hist.append(r)
        if r<=1e-9: break
        w=A@lam+q; s=np.zeros(n)
        for j in range(n):
            k=P['nof'][j]
            if k>=0: s[k]+=P['mu'][j]*abs(w[j])
    print(f.split('/')[-1], n, 'outer',len(hist), ' '.join('%.0e'%h if not isinstance(h,str) else h for h in hist[:8]), '...', hist[-1] if isinstance(hist[-1],str) else '%.1e'%hist[-1])
