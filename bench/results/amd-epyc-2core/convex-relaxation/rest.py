"""The relaxation warm-started, on islands dumped from resumed resting piles with the committed
solver's warm start (the previous step's answer and row states): Newton steps in the relaxation's
pieces (homotopy.py at theta = 0), the first in the warm state, each next one in the natural
map's state at the last point, stopping on a repeated state or after 6; then the cold interior
point (ccp.py) if still unsettled. Prints per island the coupled solver's factorisations and the
relaxation's. Islands whose warm start is all zero (a resumed run's first, cold step) are skipped.
Usage: python3 rest.py FILES"""
import sys
import numpy as np
from ccp import load, ipm
from homotopy import natural, piece_solve


def warm_relaxation(P, tol=1e-9, newton=6):
    lam = P['warm'].copy()
    st = P['warm_state'].copy()          # 0 free, 1 lower, 2 upper (rows.hpp's RowState)
    fact = 0
    seen = set()
    for k in range(newton):
        r, nat, w = natural(P, lam, 0.0)
        if r <= tol:
            return fact, r
        if k > 0: st = nat
        key = st.tobytes()
        if key in seen: break
        seen.add(key)
        try:
            lam = piece_solve(P, lam, 0.0, st, w)
        except RuntimeError:
            break
        fact += 1
    r, _, _ = natural(P, lam, 0.0)
    if r <= tol:
        return fact, r
    f, r2, _ = ipm(P)
    return (fact + f if f is not None else None), r2


for path in sys.argv[1:]:
    P = load(path)
    if not np.any(P['warm']):
        continue
    fact, r = warm_relaxation(P)
    print(path, P['n'], 'coupled', P['settled'], P['fact'], f"{P['res']:.2g}", 'relaxation', fact, f"{r:.2g}", flush=True)
