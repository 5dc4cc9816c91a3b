"""De Saxce's fixed point on real islands: the relaxation solved again with its normals' free
velocities shifted by mu sum_t |w_t| of the last answer; at a fixed point the answer is the coupled
problem's. Prints the coupled residual after each relaxation and the factorisations so far."""
import sys
import numpy as np
from ccp import load, ipm, coupled_residual

for path in sys.argv[1:]:
    P = load(path)
    q0 = P['q'].copy()
    total = 0
    trail = []
    shift = np.zeros(P['n'])
    for outer in range(12):
        P['q'] = q0 + shift
        f, r, lam = ipm(P)
        total += f if f is not None else 60
        P['q'] = q0
        cr = coupled_residual(P, lam)
        trail.append(f"{cr:.1g}")
        if cr <= 1e-9: break
        w = P['A'] @ lam + q0
        shift = np.zeros(P['n'])
        for j in np.nonzero(P['no'] >= 0)[0]:
            shift[P['no'][j]] += P['mu'][j] * abs(w[j])
    print(path.split('/')[-1], P['n'], 'solver', f"{P['res']:.2g}", 'coupled residual after each relaxation:', ' '.join(trail), 'factorisations', total, flush=True)
