import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from blcp import *
from pdas import pdas, project
# symm: 0 the coupled matrix always; 1 the symmetric (associated) one always; in (0, 1) the symmetric
# one on the step after one shorter than symm (../continuation/ipm_sym.py).
def ipm(A,q,lo,hi,nof,mu,sigma_c=0.1,iters=60,verbose=False,mehrotra=False,symm=0.0):
    n=len(q); sc=max(np.max(np.abs(q)),1e-12); d=np.diag(A)
    fr=nof>=0
    haslo=fr|np.isfinite(lo); hashi=fr|np.isfinite(hi)
    # selector matrices: s_lo = Llo @ lam - clo ; s_hi = Lhi @ lam + chi
    Llo=np.zeros((n,n)); Lhi=np.zeros((n,n)); clo=np.zeros(n); chi=np.zeros(n)
    for j in range(n):
        if fr[j]: Llo[j,j]=1; Llo[j,nof[j]]=mu[j]; Lhi[j,j]=-1; Lhi[j,nof[j]]=mu[j]
        else:
            if np.isfinite(lo[j]): Llo[j,j]=1; clo[j]=lo[j]
            if np.isfinite(hi[j]): Lhi[j,j]=-1; chi[j]=hi[j]
    lam=np.zeros(n)
    for j in range(n):
        if not fr[j] and np.isfinite(lo[j]): lam[j]=lo[j]+0.1*sc/d[j]
    w=A@lam+q
    zlo=np.where(haslo,np.maximum(w,0)+0.1*sc,0.); zhi=np.where(hashi,np.maximum(-w,0)+0.1*sc,0.)
    best=1e99
    use_sym=[symm>=1]
    for it in range(iters):
        slo=np.where(haslo,Llo@lam-clo,1.); shi=np.where(hashi,Lhi@lam+chi,1.)
        w=A@lam+q
        m=haslo.sum()+hashi.sum()
        gap=(np.sum(zlo*slo*haslo)+np.sum(zhi*shi*hashi))/m
        # Newton: A dl - dzlo + dzhi = -(w - zlo + zhi); zlo*dslo + slo*dzlo = tau - zlo*slo
        def solve(rc_lo, rc_hi):
            # dz_lo = (rc_lo - zlo*Llo dl)/slo ; dz_hi = (rc_hi - zhi*Lhi dl)/shi

            Dlo=np.where(haslo,zlo/slo,0.); Dhi=np.where(hashi,zhi/shi,0.)
            # careful: residual row j: w_j - zlo_j + zhi_j ; d/d(dl): A dl - dzlo + dzhi
            # -dzlo = -(rc_lo - zlo*Llo dl)/slo = -rc_lo/slo + Dlo*Llo dl
            # +dzhi = (rc_hi - zhi*Lhi dl)/shi = rc_hi/shi - Dhi*Lhi dl
            M=A + Dlo[:,None]*Llo - Dhi[:,None]*Lhi
            if use_sym[0]: M=A + Llo.T@(Dlo[:,None]*Llo) + Lhi.T@(Dhi[:,None]*Lhi)
            rhs=-(w-zlo+zhi) + np.where(haslo,rc_lo/slo,0) - np.where(hashi,rc_hi/shi,0)
            dl=np.linalg.solve(M,rhs)
            dzlo=np.where(haslo,(rc_lo-zlo*(Llo@dl))/slo,0); dzhi=np.where(hashi,(rc_hi-zhi*(Lhi@dl))/shi,0)
            return dl,dzlo,dzhi
        def maxstep(x,dx,mask):
            a=1.
            for j in range(n):
                if mask[j] and dx[j]<0: a=min(a,-x[j]/dx[j])
            return a
        tau=sigma_c*gap
        if mehrotra:
            dl,dzlo,dzhi=solve(-zlo*slo*haslo,-zhi*shi*hashi)
            dslo=Llo@dl; dshi=Lhi@dl
            a=min(maxstep(slo,dslo,haslo),maxstep(shi,dshi,hashi),maxstep(zlo,dzlo,haslo),maxstep(zhi,dzhi,hashi))
            ga=(np.sum((zlo+a*dzlo)*(slo+a*dslo)*haslo)+np.sum((zhi+a*dzhi)*(shi+a*dshi)*hashi))/m
            tau=min(1,(ga/gap)**3)*gap
        dl,dzlo,dzhi=solve((tau-zlo*slo)*haslo,(tau-zhi*shi)*hashi)
        dslo=Llo@dl; dshi=Lhi@dl
        a=min(1,0.99*min(maxstep(slo,dslo,haslo),maxstep(shi,dshi,hashi),maxstep(zlo,dzlo,haslo),maxstep(zhi,dzhi,hashi)))
        lam=lam+a*dl; zlo=zlo+a*dzlo; zhi=zhi+a*dzhi
        if symm<1: use_sym[0]= a<symm
        r=resid(A,q,project(lam,lo,hi,nof,mu),lo,hi,nof,mu)
        best=min(best,r)
        if verbose: print(it,'alpha %.2e gap %.2e res %.2e'%(a,gap,r), np.round(lam[~fr],1))
        if r<1e-9: return r,it+1
    return best,iters
if __name__=='__main__':
    A,q,lo,hi,nof,mu,warm,ans=load(sys.argv[1] if len(sys.argv)>1 else __import__('os').path.join(__import__('os').path.dirname(__file__), 'island_18_rows.txt'))
    print('mehrotra', ipm(A,q,lo,hi,nof,mu,mehrotra=True,iters=60))
    for sc in [0.05,0.1,0.2,0.3,0.5,0.7]:
        print(sc, ipm(A,q,lo,hi,nof,mu,sigma_c=sc,iters=200))
