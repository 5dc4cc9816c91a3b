"""The rows of an answer by state, its distance from degeneracy, and the natural map's piece of a point."""
import numpy as np
from load import bounds
def classify(P,lam,eps=1e-9):
    w=P['A']@lam+P['q'];lo,hi=bounds(P,lam);no=P['no'];d=P['diag'];sc=np.abs(P['q']).max()
    out=[]
    for j in range(P['n']):
        atlo=abs(lam[j]-lo[j])*d[j]<=eps*sc; athi=abs(hi[j]-lam[j])*d[j]<=eps*sc if np.isfinite(hi[j]) else False
        wz=abs(w[j])<=eps*sc
        if no[j]<0:
            s='N0' if atlo and not wz else ('N+' if not atlo and wz else ('Ndeg' if atlo and wz else '??'))
        else:
            if atlo and athi: s='Tclosed'
            elif (atlo or athi) and wz: s='Tdeg'
            elif atlo or athi: s='Tslide'
            elif wz: s='Tstick'
            else: s='T??'
        out.append(s)
    return out
def strictness(P, lam):
    """min over rows of max(A_jj * distance to the nearest active bound, |w_j|) / max |q|: how far the
    answer is from a degenerate row (a row at a bound with w = 0). Closed friction rows (lambda_n = 0)
    are left out."""
    w = P['A'] @ lam + P['q']; lo, hi = bounds(P, lam); d = P['diag']; sc = np.abs(P['q']).max()
    worst = np.inf
    for j in range(P['n']):
        if P['no'][j] >= 0 and hi[j] <= lo[j]: continue
        gap = min(abs(lam[j] - lo[j]), abs(hi[j] - lam[j]) if np.isfinite(hi[j]) else np.inf) * d[j]
        worst = min(worst, max(gap, abs(w[j])) / sc)
    return worst
def natural_state(P, lam):
    """Each row's piece of the natural map at lam: 'L' or 'U' (lam - w / A_jj past that bound), else 'F'."""
    w = P['A'] @ lam + P['q']; lo, hi = bounds(P, lam); x = lam - w / P['diag']
    return ['L' if x[j] <= lo[j] else 'U' if x[j] >= hi[j] else 'F' for j in range(P['n'])]
