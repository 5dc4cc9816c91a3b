import numpy as np
def load(path):
    L=open(path).read().split('\n')
    n=int(L[0]); A=np.array([[float(v) for v in L[1+i].split()] for i in range(n)])
    meta=[L[1+n+i].split() for i in range(n)]
    q=np.array([float(m[0]) for m in meta]); lo=np.array([float(m[1]) for m in meta]); hi=np.array([float(m[2]) for m in meta])
    nof=np.array([int(m[3]) for m in meta]); mu=np.array([float(m[4]) for m in meta]); diag=np.array([float(m[5]) for m in meta])
    start=np.array([float(m[6]) for m in meta]); body=[int(m[8]) for m in meta]; sigma=np.array([float(m[9]) for m in meta])
    return dict(n=n,A=A,q=q,lo=lo,hi=hi,nof=nof,mu=mu,diag=diag,start=start,body=body,sigma=sigma)
def bounds(P,lam):
    lo=P['lo'].copy(); hi=P['hi'].copy()
    for j in range(P['n']):
        k=P['nof'][j]
        if k>=0: b=P['mu'][j]*max(0,lam[k]); lo[j]=-b; hi[j]=b
    return lo,hi
def residual(P,lam):
    w=P['A']@lam+P['q']; lo,hi=bounds(P,lam)
    proj=np.clip(lam-w/P['diag'],lo,np.maximum(lo,hi))
    return np.max(np.abs(lam-proj)*P['diag'])/max(np.max(np.abs(P['q'])),1e-12)
def lcp(P):
    """Stewart-Trinkle style LCP for normals (lo=0,hi=inf) and box friction; joint rows unsupported."""
    n=P['n']; A=P['A']; q=P['q']; nof=P['nof']; mu=P['mu']
    N=[j for j in range(n) if nof[j]<0]; T=[j for j in range(n) if nof[j]>=0]
    for j in N: assert P['lo'][j]==0 and np.isinf(P['hi'][j]), (j,P['lo'][j],P['hi'][j])
    nN,nT=len(N),len(T)
    # z = [lam_N, b+, b-, gamma]; lam = E z with lam_T = b+ - b-
    m=nN+3*nT
    E=np.zeros((n,m))
    for a,j in enumerate(N): E[j,a]=1
    for a,j in enumerate(T): E[j,nN+a]=1; E[j,nN+nT+a]=-1
    W=A@E  # w = W z + q
    M=np.zeros((m,m)); qq=np.zeros(m)
    for a,j in enumerate(N): M[a]=W[j]; qq[a]=q[j]
    for a,j in enumerate(T):
        M[nN+a]=W[j]; M[nN+a,nN+2*nT+a]+=1; qq[nN+a]=q[j]
        M[nN+nT+a]=-W[j]; M[nN+nT+a,nN+2*nT+a]+=1; qq[nN+nT+a]=-q[j]
        M[nN+2*nT+a,N.index(nof[j])]=mu[j]; M[nN+2*nT+a,nN+a]=-1; M[nN+2*nT+a,nN+nT+a]=-1
    return M,qq,E
def lemke(M,q,maxit=10000):
    m=len(q)
    if np.all(q>=0): return np.zeros(m),0
    # tableau: w - M z - d z0 = q ; basis initially w
    d=np.ones(m)
    T=np.hstack([np.eye(m),-M,-d[:,None],q[:,None]])
    basis=list(range(m))  # w vars 0..m-1, z vars m..2m-1, z0 = 2m
    r=int(np.argmin(q)); enter=2*m
    it=0
    while it<maxit:
        it+=1
        # pivot row r on column enter
        T[r]/=T[r,enter]
        for i in range(m):
            if i!=r and T[i,enter]!=0: T[i]-=T[i,enter]*T[r]
        leaving=basis[r]; basis[r]=enter
        if leaving==2*m: break
        enter = leaving+m if leaving<m else leaving-m
        col=T[:,enter]
        pos=col>1e-12
        if not pos.any(): return None,it
        ratios=np.where(pos,T[:,-1]/np.where(pos,col,1),np.inf)
        mn=ratios.min()
        cand=np.where(ratios<=mn*(1+1e-9)+1e-15)[0]
        # prefer z0 leaving
        r=next((i for i in cand if basis[i]==2*m), cand[0])
    z=np.zeros(2*m+1)
    for i,b in enumerate(basis): z[b]=T[i,-1]
    return z[m:2*m],it
def lemke_lex(M,q,maxit=20000,d=None):
    """Lemke with lexicographic degeneracy resolution. Tableau rows: basis vars = B^-1 (q | I)."""
    m=len(q)
    if np.all(q>=0): return np.zeros(m),0
    if d is None: d=np.ones(m)
    # columns: w(0..m-1), z(m..2m-1), z0(2m); RHS q and lex part I (B^-1)
    T=np.hstack([np.eye(m),-M,-d[:,None]]); R=np.hstack([q[:,None],np.eye(m)])
    basis=list(range(m))
    r=None; enter=2*m
    # initial: z0 enters, leaving row = lexmin of R[i]/d[i] with most negative q
    # choose row by lexicographic max of -R[i]/d[i] among rows -> most negative q (lex ties)
    vals=R/d[:,None]
    r=min(range(m),key=lambda i:tuple(vals[i]))
    it=0
    while it<maxit:
        it+=1
        piv=T[r,enter]; T[r]/=piv; R[r]/=piv
        for i in range(m):
            if i!=r:
                f=T[i,enter]
                if f!=0: T[i]-=f*T[r]; R[i]-=f*R[r]
        leaving=basis[r]; basis[r]=enter
        if leaving==2*m: break
        enter = leaving+m if leaving<m else leaving-m
        col=T[:,enter]
        cand=[i for i in range(m) if col[i]>1e-11]
        if not cand: return None,it
        r=min(cand,key=lambda i:tuple(R[i]/col[i]))
        # z0 leaves if it ties on the primary ratio
        mn=R[r,0]/col[r]
        for i in cand:
            if basis[i]==2*m and R[i,0]/col[i]<=mn+1e-13: r=i;break
    else: return None,it
    z=np.zeros(2*m+1)
    for i,b in enumerate(basis): z[b]=R[i,0]
    return z[m:2*m],it
def lcp_st(P):
    """Stewart-Trinkle LCP: per contact, 4 diagonal generators of the friction box and one gamma."""
    n=P['n']; A=P['A']; q=P['q']; nof=P['nof']; mu=P['mu']
    N=[j for j in range(n) if nof[j]<0]
    tang={k:[j for j in range(n) if nof[j]==k] for k in N}
    C=[k for k in N if len(tang[k])==2 and mu[tang[k][0]]>0]
    nN=len(N); nC=len(C)
    m=nN+5*nC
    E=np.zeros((n,m))
    for a,j in enumerate(N): E[j,a]=1
    gens=[(1,1),(1,-1),(-1,1),(-1,-1)]
    for c,k in enumerate(C):
        t1,t2=tang[k]
        for g,(a,b) in enumerate(gens):
            col=nN+4*c+g; E[t1,col]=a; E[t2,col]=b
    W=A@E
    M=np.zeros((m,m)); qq=np.zeros(m)
    for a,j in enumerate(N): M[a]=W[j]; qq[a]=q[j]
    G0=nN+4*nC
    for c,k in enumerate(C):
        t1,t2=tang[k]
        for g,(a,b) in enumerate(gens):
            r=nN+4*c+g
            M[r]=a*W[t1]+b*W[t2]; qq[r]=a*q[t1]+b*q[t2]; M[r,G0+c]=1
        r=G0+c; M[r,N.index(k)]=mu[t1]
        for g in range(4): M[r,nN+4*c+g]=-1
    return M,qq,E
def lemke_rev(M,q,maxit=5000,tol=1e-9):
    """Revised Lemke: basis matrix re-solved each pivot (robust, O(m^3)/pivot). Columns of [I, -M, -d]."""
    m=len(q)
    if np.all(q>=0): return np.zeros(m),0
    d=np.ones(m)
    C=np.hstack([np.eye(m),-M,-d[:,None]])
    basis=list(range(m))
    r=int(np.argmin(q)); enter=2*m
    basis[r]=enter
    leaving=r
    it=0
    while it<maxit:
        it+=1
        B=C[:,basis]
        x=np.linalg.solve(B,q)
        enter = leaving+m if leaving<m else leaving-m
        col=np.linalg.solve(B,C[:,enter])
        cs=np.max(np.abs(col))
        pos=col>tol*cs
        if not pos.any(): return None,it
        ratios=np.where(pos,np.maximum(x,0)/np.where(pos,col,1),np.inf)
        mn=ratios.min()
        cand=np.where(ratios<=mn+1e-12*max(1,abs(mn)))[0]
        rr=next((i for i in cand if basis[i]==2*m), None)
        if rr is None: rr=cand[np.argmax(col[cand])]
        leaving=basis[rr]; basis[rr]=enter
        if leaving==2*m:
            B=C[:,basis]; x=np.linalg.solve(B,q)
            z=np.zeros(2*m+1)
            for i,b in enumerate(basis): z[b]=x[i]
            return z[m:2*m],it
    return None,it
