"""Lemke's method (dense tableau, covering vector of ones) and the Stewart-Trinkle LCP of an island
without joints: per friction row t, lambda_t = p - m with a sliding speed beta_t and the slack
mu lambda_n - p - m (the box as the pyramid of its four diagonal generators)."""
import numpy as np
def lemke(M,q,maxit=5000,tol=1e-12):
    n=len(q)
    if np.all(q>=0): return np.zeros(n),0,'trivial'
    # tableau: w - M z - e z0 = q ; basis initially w
    T=np.hstack([np.eye(n),-M,-np.ones((n,1)),q.reshape(-1,1)])
    basis=list(range(n))  # var ids: w 0..n-1, z n..2n-1, z0 2n
    r=int(np.argmin(q)); entering=2*n
    it=0
    while it<maxit:
        it+=1
        # pivot on row r, column entering
        T[r]/=T[r,entering]
        for i in range(n):
            if i!=r and T[i,entering]!=0: T[i]-=T[i,entering]*T[r]
        leaving=basis[r]; basis[r]=entering
        if leaving==2*n: break
        entering = leaving+n if leaving<n else leaving-n
        col=T[:,entering]
        rhs=T[:,-1]
        cand=[i for i in range(n) if col[i]>tol]
        if not cand: return None,it,'ray'
        ratios=np.array([rhs[i]/col[i] for i in cand])
        mn=ratios.min()
        ties=[cand[k] for k in range(len(cand)) if ratios[k]<=mn+1e-12*max(1,abs(mn))]
        # prefer z0 leaving
        r=None
        for i in ties:
            if basis[i]==2*n: r=i
        if r is None: r=ties[0]
    z=np.zeros(2*n+1)
    for i,bv in enumerate(basis): z[bv]=T[i,-1]
    return z[n:2*n],it,'ok' if basis.count(2*n)==0 else 'maxit'
def st_lcp(P):
    A=P['A'];no=P['no'];n=P['n'];mu=P['mu'];q=P['q']
    N=[j for j in range(n) if no[j]<0]; Tt=[j for j in range(n) if no[j]>=0]
    assert all(P['lo'][j]==0 and P['hi'][j]==np.inf for j in N)
    nN,nT=len(N),len(Tt)
    Ann=A[np.ix_(N,N)];Ant=A[np.ix_(N,Tt)];Atn=A[np.ix_(Tt,N)];Att=A[np.ix_(Tt,Tt)]
    E=np.zeros((nT,nN))
    for k,t in enumerate(Tt): E[k,N.index(no[t])]=mu[t]
    I=np.eye(nT);Z=np.zeros
    M=np.block([[Ann,Ant,-Ant,Z((nN,nT))],[Atn,Att,-Att,I],[-Atn,-Att,Att,I],[E,-I,-I,Z((nT,nT))]])
    qq=np.concatenate([q[N],q[Tt],-q[Tt],np.zeros(nT)])
    def back(z):
        lam=np.zeros(n)
        lam[N]=z[:nN];lam[Tt]=z[nN:nN+nT]-z[nN+nT:nN+2*nT]
        return lam
    return M,qq,back
