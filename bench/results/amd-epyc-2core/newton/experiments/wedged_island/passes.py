import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from blcp import *
def qp_pgs(A,q,l,h,lam,sweeps=20000):
    d=np.diag(A)
    for s in range(sweeps):
        old=lam.copy()
        for j in range(len(q)):
            lam[j]=min(max(lam[j]-(A[j]@lam+q[j])/d[j],l[j]),h[j])
        if np.max(np.abs(lam-old)*d)<1e-15: break
    return lam
A,q,lo,hi,nof,mu,warm,ans=load(sys.argv[1] if len(sys.argv)>1 else __import__('os').path.join(__import__('os').path.dirname(__file__), 'island_18_rows.txt'))
lam=warm.copy()
for p in range(15):
    l,h=bounds(lam,lo,hi,nof,mu)
    f=nof<0; l[f]=lo[f]; h[f]=hi[f]
    lam=qp_pgs(A,q,l,h,lam.copy())
    print(p,'%.2e'%resid(A,q,lam,lo,hi,nof,mu), np.round(lam[nof<0],1))
from pdas import pdas
print('pdas from pass answers')
lam=warm.copy()
for p in range(6):
    l,h=bounds(lam,lo,hi,nof,mu)
    f=nof<0; l[f]=lo[f]; h[f]=hi[f]
    lam=qp_pgs(A,q,l,h,lam.copy())
    (r,_),it=pdas(A,q,lo,hi,nof,mu,lam.copy())
    print(p,'pdas -> %.2e in %d'%(r,it))
