import os, sys; sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "wedged_island")); sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np
from blcp import load, resid
def constraints(n,lo,hi,nof,mu):
    G=[];h=[]
    for j in range(n):
        if nof[j]>=0:
            for s in (1,-1):
                g=np.zeros(n); g[j]=s; g[nof[j]]=-mu[j]; G.append(g); h.append(0.)
        else:
            if np.isfinite(lo[j]): g=np.zeros(n); g[j]=-1; G.append(g); h.append(-lo[j])
            if np.isfinite(hi[j]): g=np.zeros(n); g[j]=1; G.append(g); h.append(hi[j])
    return np.array(G),np.array(h)
def qp(A,c,G,h,iters=100):
    n=len(c); m=len(h); x=np.zeros(n); s=np.ones(m); z=np.ones(m)
    for it in range(iters):
        rd=A@x+c+G.T@z; rp=G@x+s-h; mu_=s@z/m
        if mu_<1e-12*max(1,np.abs(c).max()): break
        if not (np.isfinite(z/s).all()): break
        K=A+G.T@np.diag(z/s)@G
        if not np.isfinite(K).all() or np.linalg.cond(K)>1e15: break
        def solve(rc):
            rhs=-rd-G.T@((z*rp-rc)/s); dx=np.linalg.solve(K,rhs); ds=-rp-G@dx; dz=(-rc-z*ds)/s
            return dx,ds,dz
        def step(v,dv):
            neg=dv<0
            return min(1,np.min(-v[neg]/dv[neg])) if neg.any() else 1.0
        dx,ds,dz=solve(s*z); a=min(step(s,ds),step(z,dz))
        sig=(((s+a*ds)@(z+a*dz)/m)/mu_)**3
        dx,ds,dz=solve(s*z+ds*dz-sig*mu_); a=min(1,0.99*min(step(s,ds),step(z,dz)))
        x+=a*dx; s+=a*ds; z+=a*dz
    # polish: active set from z>s, equality KKT
    act=z>s
    Ga=G[act]; na=Ga.shape[0]
    K=np.block([[A,Ga.T],[Ga,np.zeros((na,na))]])
    sol=np.linalg.lstsq(K,np.concatenate([-c,h[act]]),rcond=None)[0]
    xp=sol[:n]; zp=sol[n:]
    if (G@xp<=h+1e-12*max(1,np.abs(xp).max())).all() and (zp>=-1e-12).all(): return xp
    return x
