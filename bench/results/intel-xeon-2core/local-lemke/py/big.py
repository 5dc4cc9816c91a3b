import numpy as np, sys, time
from isl import lcp_st, lcp, lemke_rev, residual, bounds
def loadbin(path):
    with open(path,'rb') as f:
        n=int(np.fromfile(f,dtype=np.int32,count=1)[0])
        A=np.fromfile(f,dtype=np.float64,count=n*n).reshape(n,n)  # column-major, symmetric anyway
        v=[np.fromfile(f,dtype=np.float64,count=n) for _ in range(9)]
    q,lo,hi,nof,mu,diag,best,st,start=v
    return dict(n=n,A=A.T.copy(),q=q,lo=lo,hi=hi,nof=nof.astype(int),mu=mu,diag=diag,best=best,st=st.astype(int),start=start,body=[0]*n)
def fw(P,lam):
    w=P['A']@lam+P['q']; lo,hi=bounds(P,lam)
    proj=np.clip(lam-w/P['diag'],lo,np.maximum(lo,hi))
    return (lam-proj)*P['diag']/max(np.max(np.abs(P['q'])),1e-12), w
def project(P,lam):
    lam=lam.copy(); n=P['n']
    for j in range(n):
        if P['nof'][j]<0: lam[j]=min(max(lam[j],P['lo'][j]),P['hi'][j])
    for j in range(n):
        k=P['nof'][j]
        if k>=0: b=P['mu'][j]*max(0,lam[k]); lam[j]=min(max(lam[j],-b),b)
    return lam
def state_of(P,lam,w):
    """0 free,1 lower,2 upper by the natural map point x = lam - w/diag"""
    n=P['n']; st=np.zeros(n,int)
    x=lam-w/P['diag']
    for j in range(n):
        k=P['nof'][j]
        if k<0:
            st[j]=1 if x[j]<=P['lo'][j] else 2 if x[j]>=P['hi'][j] else 0
        else:
            b=P['mu'][j]*max(0,lam[k])
            st[j]=2 if (x[j]>=b and x[j]>0) else 1 if (x[j]<=-b and x[j]<0) else 0
    return st
def contact_of(P):
    n=P['n']; c=np.arange(n)
    for j in range(n):
        if P['nof'][j]>=0: c[j]=P['nof'][j]
    return c
def local_solve(P,lam,st,T):
    """Rows R = not T keep equations of state st; solve exact BLCP on T (Schur complement), return full lam."""
    n=P['n']; A=P['A']; q=P['q']
    Tset=np.zeros(n,bool); Tset[T]=True
    R=np.where(~Tset)[0]; T=np.where(Tset)[0]
    # R equations: E_RR lam_R + E_RT lam_T = g_R
    rpos={j:i for i,j in enumerate(R)}
    nR=len(R)
    ERR=np.zeros((nR,nR)); ERT=np.zeros((nR,len(T))); g=np.zeros(nR)
    for i,j in enumerate(R):
        k=P['nof'][j]
        if k<0:
            if st[j]==0: ERR[i]=A[j,R]; ERT[i]=A[j,T]; g[i]=-q[j]
            else: ERR[i,i]=1; g[i]=P['lo'][j] if st[j]==1 else P['hi'][j]
        else:
            if st[k]!=0 or k not in rpos: ERR[i,i]=1; g[i]=0  # normal not free: closed
            elif st[j]==0: ERR[i]=A[j,R]; ERT[i]=A[j,T]; g[i]=-q[j]
            else:
                ERR[i,i]=1; ERR[i,rpos[k]]=-(P['mu'][j] if st[j]==2 else -P['mu'][j]); g[i]=0
    lu=np.linalg.solve  # dense
    Pm=-np.linalg.solve(ERR,ERT); p0=np.linalg.solve(ERR,g)
    W=A[np.ix_(T,T)]+A[np.ix_(T,R)]@Pm; w0=q[T]+A[np.ix_(T,R)]@p0
    tl={j:i for i,j in enumerate(T)}
    PT=dict(n=len(T),A=W,q=w0,lo=P['lo'][T],hi=P['hi'][T],nof=np.array([tl[P['nof'][j]] if P['nof'][j]>=0 else -1 for j in T]),mu=P['mu'][T],diag=np.abs(np.diag(W)),body=[0]*len(T))
    M,qq,E=lcp_st(PT)
    dg=np.abs(np.diag(M)); s=np.where(dg>0,1/np.sqrt(np.where(dg>0,dg,1)),0); s[s==0]=np.exp(np.mean(np.log(s[s>0]))) if (s>0).any() else 1
    S=np.diag(s)
    z,it=lemke_rev(S@M@S,S@qq)
    if z is None:
        M,qq,E=lcp(PT)
        dg=np.abs(np.diag(M)); s=np.where(dg>0,1/np.sqrt(np.where(dg>0,dg,1)),0); s[s==0]=np.exp(np.mean(np.log(s[s>0])))
        S=np.diag(s); z,it=lemke_rev(S@M@S,S@qq)
        if z is None: return None,it
    lamT=E@(S@z)
    out=np.zeros(n); out[T]=lamT; out[R]=Pm@lamT+p0
    return out,it
