import sys, numpy as np, glob, os, warnings
warnings.simplefilter('ignore')
here=os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0,os.path.join(here,'../../intel-xeon-2core/local-lemke/py'))
sys.path.insert(0,os.path.join(here,'../newton/experiments/wedged_island'))
from isl import load, residual
from ipm import ipm
from pdas import pdas
# A proximal term on the normal impulses' modes that exert no wrench (null space of (A - Sigma)_NN).
def modify(P, rho):
    A=P['A'].copy(); q=P['q'].copy(); n=P['n']
    N=[j for j in range(n) if P['nof'][j]<0]
    B=(A-np.diag(P['sigma']))[np.ix_(N,N)]
    d=np.diag(B); s=1/np.sqrt(d); Bs=B*s[:,None]*s[None,:]
    ev,V=np.linalg.eigh(Bs)
    null=V[:,ev<1e-8]            # scaled modes
    k=null.shape[1]
    if k:
        Pn=np.diag(1/s)@(null@null.T)@np.diag(1/s)  # D^1/2 P D^1/2: rho times it adds rho D on the modes
        A[np.ix_(N,N)]+=rho*Pn
        q[N]-=rho*Pn@P['start'][N]
    return A,q,k
rho=float(sys.argv[2]) if len(sys.argv)>2 else 1e-3
for f in sorted(glob.glob(os.path.join(sys.argv[1],'island_*.txt')),key=lambda p:int(p.split('_')[-1][:-4])):
    P=load(f); n=P['n']; lo,hi,nof,mu=P['lo'],P['hi'],P['nof'],P['mu']
    r0,it0=ipm(P['A'],P['q'],lo,hi,nof,mu,mehrotra=True,iters=60)
    A,q,k=modify(P,rho)
    r1,it1=ipm(A,q,lo,hi,nof,mu,mehrotra=True,iters=60)
    print(f.split('/')[-1], n, 'null modes',k, 'ipm base %.1e in %d'%(r0,it0), ' null-prox %.1e in %d'%(r1,it1))
