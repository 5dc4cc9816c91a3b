import numpy as np, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
from blcp import *
from pdas import piece, project
def pgssm(A,q,lo,hi,nof,mu,lam,k,budget=40,newton_per_round=1):
    fac=0; sweeps=0
    while fac<budget:
        lam=pgs(A,q,lo,hi,nof,mu,lam,k); sweeps+=k
        r0=resid(A,q,lam,lo,hi,nof,mu)
        if r0<=1e-9: return r0,fac,sweeps
        x=lam
        for t in range(newton_per_round):
            E,g,s=piece(A,q,lo,hi,nof,mu,x); fac+=1
            x=project(np.linalg.solve(E,g),lo,hi,nof,mu)
            r=resid(A,q,x,lo,hi,nof,mu)
            if r<=1e-9: return r,fac,sweeps
            if r<r0: lam=x; r0=r
    return resid(A,q,lam,lo,hi,nof,mu),fac,sweeps
if __name__=='__main__':
    A,q,lo,hi,nof,mu,warm,ans=load(sys.argv[1] if len(sys.argv)>1 else __import__('os').path.join(__import__('os').path.dirname(__file__), 'island_18_rows.txt'))
    for start,name in [(warm,'warm'),(np.zeros(len(q)),'zero')]:
        for k in [1,2,5,10,20]:
            for npr in [1,2]:
                print(name,'k',k,'newton/round',npr,'-> res %.2e fac %d sweeps %d'%pgssm(A,q,lo,hi,nof,mu,start.copy(),k,40,npr))
