# A second level of elimination over groups of the interface's bodies, estimated in flops on a
# dumped interface S (dump.patch): recursive spectral bisection of its body graph into 2, 4, 8
# groups; per group the sparse LU of its own bodies (SciPy/SuperLU, COLAMD) plus X_g and its Schur
# block formed dense as substructured_system.cpp forms them; the top level's sparse LU with each
# group's boundary a clique. Usage: /usr/bin/python3 nd.py /tmp/dump/m*.bin
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as sla, sys
def load(fn):
    b=open(fn,'rb').read(); n,nnz=np.frombuffer(b[:8],np.int32)
    o=8; p=np.frombuffer(b[o:o+4*(n+1)],np.int32); o+=4*(n+1)
    i=np.frombuffer(b[o:o+4*nnz],np.int32); o+=4*nnz; x=np.frombuffer(b[o:o+8*nnz],np.float64)
    return sp.csc_matrix((x,i,p),shape=(n,n))
def lu_flops(A):
    # flops of sparse LU with COLAMD ordering, from nnz of L and U column counts: sum over k of |L_k|*|U_k| roughly
    lu=sla.splu(sp.csc_matrix(A),permc_spec='COLAMD',diag_pivot_thresh=0.0)
    L=lu.L.tocsc(); U=lu.U.tocsr()
    lc=np.diff(L.indptr)-1; ur=np.diff(U.indptr)-1
    return int(np.sum(lc+2*lc*ur)), L.nnz+U.nnz
for fn in sys.argv[1:]:
    A=load(fn); n=A.shape[0]; nb=n//6
    B=(abs(A)>0).astype(float); G=sp.csr_matrix((nb,nb))
    R=sp.csr_matrix(sp.kron(sp.eye(nb),np.ones((1,6))))  # body aggregation
    G=sp.csr_matrix(R@B@R.T); G=sp.csr_matrix(G+G.T); G.setdiag(0); G=(G>0).astype(float)
    f0,nz0=lu_flops(A)
    print(fn,'n',n,'bodies',nb,'avg deg',G.sum()/nb,'LU flops',f0)
    deg=np.array(G.sum(1)).ravel(); Lap=sp.diags(deg)-G
    # recursive spectral bisection into 2^k groups
    def bisect(idx):
        if len(idx)<4: return [idx]
        Ls=Lap[idx][:,idx].toarray(); w,v=np.linalg.eigh(Ls); f=v[:,1]; m=np.median(f)
        return [idx[f<=m], idx[f>m]]
    for k in (1,2,3):
        groups=[np.arange(nb)]
        for _ in range(k): groups=[h for g in groups for h in bisect(g)]
        gid=np.empty(nb,int)
        for gi,g in enumerate(groups): gid[g]=gi
        Gc=G.tocoo(); cross=gid[Gc.row]!=gid[Gc.col]
        boundary=np.zeros(nb,bool); boundary[Gc.row[cross]]=True
        nsep=boundary.sum()
        # group interior flops and top-level size
        worst=0; total=0
        for gi in range(len(groups)):
            ib=np.where((gid==gi)&~boundary)[0]; kb=np.where((gid==gi)&boundary)[0]
            iu=(ib[:,None]*6+np.arange(6)).ravel(); ku=(kb[:,None]*6+np.arange(6)).ravel()
            if len(iu)==0: continue
            fl,nz=lu_flops(A[iu][:,iu]); fl+= 2*nz*len(ku) + 2*len(ku)*len(iu)*len(ku)  # factor + X + schur (dense-ish upper bound)
            worst=max(worst,fl); total+=fl
        top=6*nsep
        # top level: sparse pattern = S among boundary + clique per group's boundary
        kbody=np.where(boundary)[0]
        T=G[kbody][:,kbody].toarray()>0
        for gi in range(len(groups)):
            m=gid[kbody]==gi; T[np.ix_(m,m)]=True
        T=sp.csc_matrix(np.kron(T.astype(float)+np.eye(len(kbody)),np.ones((6,6)))+sp.eye(top)*100)
        Tv=T.copy(); Tv.data=np.random.rand(len(Tv.data)); Tv=Tv+sp.eye(top)*top
        ft,_=lu_flops(Tv)
        print(f'  {len(groups)} groups: separator bodies {nsep}, worst group flops {worst:.2e}, total groups {total:.2e}, top n {top} flops {ft:.2e}, critical {worst+ft:.2e} vs {f0:.2e}')
