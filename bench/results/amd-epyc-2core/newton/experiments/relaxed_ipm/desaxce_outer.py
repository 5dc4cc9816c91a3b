import os, sys; sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "wedged_island")); sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sys, numpy as np
from qp import constraints
from blcp import load, resid, bounds
import scipy.optimize as so
# exact QP via scipy's nnls-free approach: solve QP with 'SLSQP'? use active-set polishing of an IPM iterate instead.
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "qp.py")).read().split('def qp')[0])
def qp_ipm(A,c,G,h,tol=1e-15):
    n=len(c); m=len(h); x=np.zeros(n); s=np.ones(m); z=np.ones(m)
    for it in range(200):
        rd=A@x+c+G.T@z; rp=G@x+s-h; mu_=s@z/m
        if mu_<tol*max(1,np.abs(c).max()): break
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
    return x,s,z,it
f=sys.argv[1]
A,q,lo,hi,nof,mu,warm,ans=load(f); n=len(q); G,h=constraints(n,lo,hi,nof,mu)
shift=np.zeros(n)
for k in range(25):
    x,s_,z,it=qp_ipm(A,q+shift,G,h)
    w=A@x+q; r=resid(A,q,x,lo,hi,nof,mu)
    rd=A@x+q+shift+G.T@z
    print(k,'ipm its',it,'KKT rd %.1e'%np.abs(rd).max(),'gap %.1e'%(s_@z/len(h)),'coupled %.2e'%r)
    new=np.zeros(n)
    for j in range(n):
        if nof[j]>=0: new[nof[j]]+=mu[j]*abs(w[j])
    shift=new
