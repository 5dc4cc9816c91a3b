import sys, numpy as np
import os
sys.path.insert(0,os.path.join(os.path.dirname(os.path.abspath(__file__)),'../../intel-xeon-2core/local-lemke/py'))
from isl import load, residual
# Piecewise-linear homotopy on the normal map N(z) = A P(z) + q + D (z - P(z)), H = N(z) - (1-t) N(z0).
FREE,LOW,UP,ZERO=0,1,2,3
def lam_of(P,z,st):
    n=P['n']; lam=np.zeros(n)
    for j in range(n):
        if P['nof'][j]<0:
            lam[j]= z[j] if st[j]==FREE else (P['lo'][j] if st[j]==LOW else P['hi'][j])
    for j in range(n):
        k=P['nof'][j]
        if k>=0:
            b=P['mu'][j]*lam[k]
            lam[j]= 0 if st[j]==ZERO else (z[j] if st[j]==FREE else (b if st[j]==UP else -b))
    return lam
def lin(P,st):
    """lam = Pm z + c for state st."""
    n=P['n']; Pm=np.zeros((n,n)); c=np.zeros(n)
    for j in range(n):
        if P['nof'][j]<0:
            if st[j]==FREE: Pm[j,j]=1
            else: c[j]=P['lo'][j] if st[j]==LOW else P['hi'][j]
    for j in range(n):
        k=P['nof'][j]
        if k>=0 and st[j]!=ZERO:
            if st[j]==FREE: Pm[j,j]=1
            else:
                s=1 if st[j]==UP else -1
                Pm[j]=s*P['mu'][j]*Pm[k]; c[j]=s*P['mu'][j]*c[k]
    return Pm,c
def state_of(P,z):
    n=P['n']; st=[FREE]*n
    for j in range(n):
        if P['nof'][j]<0:
            st[j]=LOW if z[j]<=P['lo'][j] else UP if z[j]>=P['hi'][j] else FREE
    lam=lam_of(P,z,st)
    for j in range(n):
        k=P['nof'][j]
        if k>=0:
            if st[k]==LOW: st[j]=ZERO
            else:
                b=P['mu'][j]*lam[k]
                st[j]=UP if z[j]>=b else LOW if z[j]<=-b else FREE
    return st
def constraints(P,st):
    """rows (a, beta, row, kind): a.z+beta>=0 within the piece; kind names the face."""
    n=P['n']; Pm,c=lin(P,st); out=[]
    for j in range(n):
        e=np.zeros(n); e[j]=1
        k=P['nof'][j]
        if k<0:
            lo,hi=P['lo'][j],P['hi'][j]
            if st[j]==FREE:
                if np.isfinite(lo): out.append((e,-lo,j,'lo'))
                if np.isfinite(hi): out.append((-e,hi,j,'hi'))
            elif st[j]==LOW: out.append((-e,lo,j,'lo'))
            else: out.append((e,-hi,j,'hi'))
        elif st[j]!=ZERO:
            bz=P['mu'][j]*Pm[k]; bc=P['mu'][j]*c[k]   # b = bz.z + bc
            if st[j]==FREE:
                out.append((bz-e,bc,j,'hi')); out.append((bz+e,bc,j,'lo'))
            elif st[j]==UP: out.append((e-bz,-bc,j,'hi'))
            else: out.append((-e-bz,-bc,j,'lo'))
    return out
def N_of(P,z,st):
    lam=lam_of(P,z,st); return P['A']@lam+P['q']+P['diag']*(z-lam)
def path(P,z0,maxpiv=2000):
    n=P['n']; D=P['diag']; A=P['A']
    st=state_of(P,z0); r0=N_of(P,z0,st); z=z0.copy(); t=0.0; dt=1.0; piv=0
    scale=max(np.abs(P['q']).max(),1e-12)
    while piv<maxpiv:
        Pm,c=lin(P,st); M=A@Pm+np.diag(D)@(np.eye(n)-Pm)
        try: dz=-np.linalg.solve(M,r0)*dt
        except np.linalg.LinAlgError: return None,piv,'singular'
        # first face hit
        smin=np.inf; hit=None
        if dt>0: smin=(1-t)/dt; hit='end'
        for a,beta,j,kind in constraints(P,st):
            g=a@z+beta; d=a@dz
            if d< -1e-14*np.abs(a).sum()*np.abs(dz).max():
                s=max(g,0)/(-d)
                if s<smin: smin=s; hit=(j,kind)
        if hit is None: return None,piv,'ray'
        z=z+smin*dz; t=t+smin*dt
        if hit=='end': return lam_of(P,z,st),piv,'ok'
        piv+=1
        j,kind=hit
        old=st[:]
        # move row j across its face
        k=P['nof'][j]
        if k<0:
            if st[j]==FREE: st[j]=LOW if kind=='lo' else UP
            else: st[j]=FREE
            # friction of a normal that closes or opens
            for i in range(n):
                if P['nof'][i]==j:
                    if st[j]==LOW: st[i]=ZERO
                    elif old[j]==LOW: st[i]=UP if z[i]>0 else LOW if z[i]<0 else FREE
        else:
            if st[j]==FREE: st[j]=LOW if kind=='lo' else UP
            else: st[j]=FREE
        # orientation: the crossed face's function must grow into the new piece
        Pm2,c2=lin(P,st); M2=A@Pm2+np.diag(D)@(np.eye(n)-Pm2)
        try: d2=-np.linalg.solve(M2,r0)
        except np.linalg.LinAlgError: return None,piv,'singular'
        # continuity: z must move away from the face on the new side; compare sign of the face's crossing
        # the old piece's face function a.z decreased; in the new piece the same face (with opposite
        # sign) must increase: use a_old . dz_new < 0 as 'continues across'
        a_old=[a for a,beta,jj,kk in constraints(P,old) if jj==j and kk==kind][0]
        dt = 1.0 if a_old@d2 < 0 else -1.0
    return None,piv,'maxpiv'
import glob
for f in sorted(glob.glob(os.path.join(sys.argv[1],'island_*.txt')),key=lambda p:int(p.split('_')[-1][:-4])):
    P=load(f); n=P['n']
    lam0=P['start']; w0=P['A']@lam0+P['q']; z0=lam0-w0/P['diag']
    lam,piv,why=path(P,z0)
    res=residual(P,lam) if lam is not None else float('nan')
    print(f.split('/')[-1], n, 'start res %.1e'%residual(P,np.clip(lam0,-1e300,1e300)), why, 'pivots',piv, 'res %.1e'%res)
