import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from blcp import *
def piece(A,q,lo,hi,nof,mu,lam):
    n=len(q); w=A@lam+q; d=np.diag(A)
    E=np.zeros((n,n)); g=np.zeros(n); st=[]
    eq={}
    for j in range(n):
        if nof[j]>=0: continue
        x=lam[j]-w[j]/d[j]
        if x<=lo[j]: E[j,j]=1; g[j]=lo[j]; eq[j]='L'
        elif x>=hi[j]: E[j,j]=1; g[j]=hi[j]; eq[j]='U'
        else: E[j]=A[j]; g[j]=-q[j]; eq[j]='F'
    for j in range(n):
        k=nof[j]
        if k<0: continue
        if eq[k]!='F' or lam[k]<0: E[j,j]=1; g[j]=0; eq[j]='0'; continue
        b=mu[j]*max(0,lam[k]); x=lam[j]-w[j]/d[j]
        if x>=b and x>0: E[j,j]=1; E[j,k]=-mu[j]; eq[j]='U'
        elif x<=-b and x<0: E[j,j]=1; E[j,k]=mu[j]; eq[j]='L'
        else: E[j]=A[j]; g[j]=-q[j]; eq[j]='F'
    return E,g,''.join(eq[j] for j in range(n))
def project(lam,lo,hi,nof,mu):
    lam=lam.copy()
    f=nof<0
    lam[f]=np.clip(lam[f],lo[f],hi[f])
    l,h=bounds(lam,lo,hi,nof,mu)
    lam[~f]=np.clip(lam[~f],l[~f],h[~f])
    return lam
def pdas(A,q,lo,hi,nof,mu,lam,iters=40,verbose=False):
    best=(resid(A,q,project(lam,lo,hi,nof,mu),lo,hi,nof,mu),lam)
    seen=set()
    for it in range(iters):
        E,g,s=piece(A,q,lo,hi,nof,mu,lam)
        if s in seen:
            if verbose: print('  repeat state', it)
            return best,it
        seen.add(s)
        lam=np.linalg.solve(E,g)
        r=resid(A,q,project(lam,lo,hi,nof,mu),lo,hi,nof,mu)
        if verbose: print('  pdas',it,s,'%.2e'%r)
        if r<best[0]: best=(r,project(lam,lo,hi,nof,mu))
        if r<1e-9: return best,it+1
    return best,iters
if __name__=='__main__':
    A,q,lo,hi,nof,mu,warm,ans=load()
    for k in [0,1,2,5,10,20,50,100,200,500]:
        lam=pgs(A,q,lo,hi,nof,mu,np.zeros(len(q)),k)
        (r,l),it=pdas(A,q,lo,hi,nof,mu,lam)
        print('pgs',k,'res before %.2e'%resid(A,q,lam,lo,hi,nof,mu),'pdas -> %.2e'%r,'iters',it)
    print('from warm'); pdas(A,q,lo,hi,nof,mu,warm,verbose=True)
    print('from ans'); pdas(A,q,lo,hi,nof,mu,ans,verbose=True)
