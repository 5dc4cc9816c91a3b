"""From the Lemke answer's natural-map state, the linear system of that piece (free rows w = 0,
rows at a bound fixed there, friction at the edge of its box tied to +-mu lambda_n) solved from
scratch: its residual. Usage: python3 one_step.py DIR"""
import sys
from pathlib import Path
import numpy as np
from load import bounds, lcp, lemke, load, residual

for path in sorted(Path(sys.argv[1]).glob("*.txt"), key=lambda p: int(p.stem)):
    P = load(str(path)); n = P['n']; A = P['A']; q = P['q']; no = P['no']; mu = P['mu']; d = P['diag']
    M, qq, E_z = lcp(P)
    z, _ = lemke(M, qq)
    if z is None: print(path.name, 'ray'); continue
    lam = E_z @ z; w = A @ lam + q; lo, hi = bounds(P, lam)
    E = np.zeros((n, n)); g = np.zeros(n)
    for j in range(n):
        x = lam[j] - w[j] / d[j]
        if no[j] < 0:
            if x <= lo[j]: E[j, j] = 1; g[j] = lo[j]
            else: E[j] = A[j]; g[j] = -q[j]
        elif hi[j] <= 0: E[j, j] = 1
        elif x >= hi[j]: E[j, j] = 1; E[j, no[j]] = -mu[j]
        elif x <= lo[j]: E[j, j] = 1; E[j, no[j]] = mu[j]
        else: E[j] = A[j]; g[j] = -q[j]
    x = np.linalg.solve(E, g)
    print(f"{path.name}: one step in the answer's state: residual {residual(P, x):.2g}")
