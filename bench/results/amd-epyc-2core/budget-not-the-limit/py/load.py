"""Reads an island dumped by replay_budget.patch (DUMP=1): rows, bodies; per row q, lo, hi, its
normal (-1: none), mu, sigma, warm start, warm state and its row of A; then the solver's best
iterate. The bounds, the natural map's residual (DESIGN.md §3), the Stewart-Trinkle LCP and
Lemke's method are those of the earlier experiment's ../../../intel-xeon-2core/local-lemke/py/isl.py."""
import sys
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[3] / 'intel-xeon-2core/local-lemke/py'))
from isl import bounds, lcp, lemke, residual  # noqa: E402,F401  (re-exported)
def load(path):
    L=open(path).read().split('\n')
    n,b=map(int,L[0].split())
    q=np.zeros(n);lo=np.zeros(n);hi=np.zeros(n);no=np.zeros(n,int);mu=np.zeros(n);sg=np.zeros(n);warm=np.zeros(n);st=np.zeros(n,int)
    A=np.zeros((n,n))
    for i in range(n):
        t=L[1+i].split()
        q[i],lo[i],hi[i]=float(t[0]),float(t[1]),float(t[2]);no[i]=int(t[3]);mu[i]=float(t[4]);sg[i]=float(t[5]);warm[i]=float(t[6]);st[i]=int(t[7])
        A[i]=[float(x) for x in t[8:]]
    best=np.array([float(x) for x in L[1+n].split()]) if len(L)>1+n and L[1+n].strip() else None
    return dict(n=n,b=b,q=q,lo=lo,hi=hi,no=no,nof=no,mu=mu,sg=sg,warm=warm,st=st,A=A,diag=np.diag(A).copy(),best=best)
