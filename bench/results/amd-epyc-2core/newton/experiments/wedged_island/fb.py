import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from blcp import *
def fb(a,b): return a+b-np.sqrt(a*a+b*b)
def Phi(A,q,lo,hi,nof,mu,lam):
    w=A@lam+q; d=np.diag(A); n=len(q); out=np.zeros(n)
    for j in range(n):
        if nof[j]>=0:
            b=mu[j]*lam[nof[j]]; l,u=-b,b
        else: l,u=lo[j],hi[j]
        wj=w[j]  # scale: phi in velocity units: (lam-l)*d vs w
        if np.isinf(l) and np.isinf(u): out[j]=wj
        elif np.isinf(u): out[j]=fb((lam[j]-l)*d[j], wj)
        else: out[j]=fb((lam[j]-l)*d[j], -fb((u-lam[j])*d[j], -wj))
    return out
def fbnewton(A,q,lo,hi,nof,mu,lam,iters=40,verbose=False):
    n=len(q); sc=max(np.max(np.abs(q)),1e-12)
    for it in range(iters):
        P=Phi(A,q,lo,hi,nof,mu,lam); psi=0.5*P@P
        r=resid(A,q,project_(lam,lo,hi,nof,mu),lo,hi,nof,mu)
        if verbose: print(it,'psi %.2e res %.2e'%(psi,r))
        if r<1e-9: return r,it
        J=np.zeros((n,n)); h=1e-7*max(1,np.max(np.abs(lam)))
        for c in range(n):
            e=np.zeros(n); e[c]=h
            J[:,c]=(Phi(A,q,lo,hi,nof,mu,lam+e)-P)/h
        try: d=np.linalg.solve(J,-P)
        except: d=-J.T@P
        g=J.T@P
        if g@d > -1e-12*np.linalg.norm(g)*np.linalg.norm(d): d=-g
        t=1
        while t>1e-12:
            P2=Phi(A,q,lo,hi,nof,mu,lam+t*d)
            if 0.5*P2@P2 <= psi + 1e-4*t*(g@d): break
            t*=0.5
        lam=lam+t*d
    return resid(A,q,project_(lam,lo,hi,nof,mu),lo,hi,nof,mu),iters
def project_(lam,lo,hi,nof,mu):
    from pdas import project
    return project(lam,lo,hi,nof,mu)
if __name__=='__main__':
    A,q,lo,hi,nof,mu,warm,ans=load(sys.argv[1] if len(sys.argv)>1 else __import__('os').path.join(__import__('os').path.dirname(__file__), 'island_18_rows.txt'))
    for nm,st in [('zero',np.zeros(len(q))),('warm',warm)]:
        print(nm, fbnewton(A,q,lo,hi,nof,mu,st.copy(),60,verbose=True))
