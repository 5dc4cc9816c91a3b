import os, sys; sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "wedged_island")); sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sys, numpy as np
from qp import constraints, qp
from blcp import load, resid
def moving(A,q,lo,hi,nof,mu,G,h,iters=60):
    n=len(q); m=len(h); x=np.zeros(n); s=np.ones(m); z=np.ones(m); hist=[]
    for it in range(iters):
        w=A@x+q; c=q.copy()
        for j in range(n):
            if nof[j]>=0: c[nof[j]]+=mu[j]*abs(w[j])
        rd=A@x+c+G.T@z; rp=G@x+s-h; mu_=s@z/m
        r=resid(A,q,x,lo,hi,nof,mu); hist.append(r)
        if r<1e-10: break
        K=A+G.T@np.diag(z/s)@G
        def solve(rc):
            rhs=-rd-G.T@((z*rp-rc)/s); dx=np.linalg.solve(K,rhs); ds=-rp-G@dx; dz=(-rc-z*ds)/s
            return dx,ds,dz
        def step(v,dv):
            neg=dv<0
            return min(1,np.min(-v[neg]/dv[neg])) if neg.any() else 1.0
        try:
            dx,ds,dz=solve(s*z)
        except Exception: break
        a=min(step(s,ds),step(z,dz))
        sig=(((s+a*ds)@(z+a*dz)/m)/mu_)**3
        try:
            dx,ds,dz=solve(s*z+ds*dz-sig*mu_)
        except Exception: break
        a=min(1,0.99*min(step(s,ds),step(z,dz)))
        x+=a*dx; s+=a*ds; z+=a*dz
    return it,r
def outer(A,q,lo,hi,nof,mu,G,h,iters=30):
    n=len(q); shift=np.zeros(n)
    for k in range(iters):
        lam=qp(A,q+shift,G,h); w=A@lam+q; r=resid(A,q,lam,lo,hi,nof,mu)
        if r<1e-10: break
        shift=np.zeros(n)
        for j in range(n):
            if nof[j]>=0: shift[nof[j]]+=mu[j]*abs(w[j])
    return k,r
for f in sys.argv[1:]:
    A,q,lo,hi,nof,mu,warm,ans=load(f)
    G,h=constraints(len(q),lo,hi,nof,mu)
    print(f,len(q),'moving IPM it %d res %.2e'%moving(A,q,lo,hi,nof,mu,G,h))
