"""Reads an island dumped by replay_budget.patch (DUMP=1): rows, bodies; per row q, lo, hi, its
normal (-1: none), mu, sigma, warm start, warm state and its row of A; then the solver's best
iterate. The natural map and its residual in the solver's scaling (DESIGN.md §3)."""
import numpy as np
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
    return dict(n=n,b=b,q=q,lo=lo,hi=hi,no=no,mu=mu,sg=sg,warm=warm,st=st,A=A,d=np.diag(A).copy(),best=best)
def bounds(P,lam):
    lo=P['lo'].copy();hi=P['hi'].copy()
    for j in range(P['n']):
        if P['no'][j]>=0:
            h=P['mu'][j]*max(0,lam[P['no'][j]]);lo[j]=-h;hi[j]=h
    return lo,hi
def resid(P,lam):
    w=P['A']@lam+P['q'];lo,hi=bounds(P,lam);d=P['d']
    F=(lam-np.clip(lam-w/d,lo,np.maximum(lo,hi)))*d
    return np.max(np.abs(F))/max(np.max(np.abs(P['q'])),1e-12),F
