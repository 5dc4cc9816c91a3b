import numpy as np, sys
def load(p=__import__('os').path.join(__import__('os').path.dirname(__file__), 'island_18_rows.txt')):
    L=open(p).read().split('\n')
    n=int(L[0]); A=np.array([[float(x) for x in L[1+c].split()] for c in range(n)]).T
    rest=[l.split() for l in L[1+n:1+2*n]]
    q=np.array([float(r[0]) for r in rest]); lo=np.array([float(r[1]) for r in rest]); hi=np.array([float(r[2]) for r in rest])
    nof=np.array([int(r[3]) for r in rest]); mu=np.array([float(r[4]) for r in rest])
    warm=np.array([float(r[5]) for r in rest]); ans=np.array([float(r[6]) for r in rest])
    return A,q,lo,hi,nof,mu,warm,ans
def bounds(lam,lo,hi,nof,mu):
    l=lo.copy(); h=hi.copy()
    f=nof>=0
    h[f]=mu[f]*np.maximum(0,lam[nof[f]]); l[f]=-h[f]
    return l,h
def resid(A,q,lam,lo,hi,nof,mu):
    w=A@lam+q; d=np.diag(A); l,h=bounds(lam,lo,hi,nof,mu)
    F=lam-np.clip(lam-w/d,l,np.maximum(l,h))
    return np.max(np.abs(F*d))/max(np.max(np.abs(q)),1e-12)
def pgs(A,q,lo,hi,nof,mu,lam,sweeps):
    d=np.diag(A); n=len(q)
    order=[j for j in range(n) if nof[j]<0]+[j for j in range(n) if nof[j]>=0]
    for s in range(sweeps):
        for j in order:
            w=A[j]@lam+q[j]
            if nof[j]>=0: b=mu[j]*max(0,lam[nof[j]]); l,h=-b,b
            else: l,h=lo[j],hi[j]
            lam[j]=min(max(lam[j]-w/d[j],l),h)
    return lam
if __name__=='__main__':
    A,q,lo,hi,nof,mu,warm,ans=load()
    print('cond A',np.linalg.cond(A), 'diag', np.diag(A))
    print('answer residual', resid(A,q,ans,lo,hi,nof,mu))
    lam=np.zeros(len(q))
    for k in range(8):
        lam=pgs(A,q,lo,hi,nof,mu,lam,1000*(2**k))
        print('pgs', 1000*(2**(k+1))-1000, resid(A,q,lam,lo,hi,nof,mu))
    print(lam)
