"""From the convex relaxation to the coupled problem: P(theta) has the normals' complementarity on
w_n - (1 - theta) mu sum_t |w_t| (theta = 0: the relaxation, solved by ccp.py's interior point;
theta = 1: the coupled problem of DESIGN.md section 3). theta is raised in steps, each solved by
Newton steps in the pieces of P(theta)'s natural map (the state of the last point), from the last
answer; a step that does not settle within `inner` Newton steps is halved."""
import sys
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from ccp import load, ipm, coupled_residual, natural


def piece_solve(P, lam, theta, state, w):
    n, no, mu, A = P['n'], P['no'], P['mu'], P['A']
    rows, g = [], np.zeros(n)
    Acsr = A.tocsr()
    closed = np.zeros(n, bool)
    for j in range(n):
        if no[j] < 0 and state[j] != 0: closed[j] = True
    f = np.nonzero(no >= 0)[0]
    # normals' free equations: A_n - (1 - theta) mu sum_t sign(w_t) A_t
    comb = {}
    for t in f:
        if state[t] != 0 and not closed[no[t]] and lam[no[t]] > 0:
            comb.setdefault(no[t], []).append(t)
    E = sp.lil_matrix((n, n))
    for j in range(n):
        if no[j] >= 0:
            nn = no[j]
            if closed[nn]:
                E[j, j] = 1.0; g[j] = 0.0
            elif state[j] == 0:
                E[j, :] = Acsr[j]; g[j] = -P['q'][j]
            else:
                s = 1.0 if state[j] == 2 else -1.0
                E[j, j] = 1.0; E[j, nn] = -s * mu[j]; g[j] = 0.0
        elif state[j] != 0:
            E[j, j] = 1.0; g[j] = P['lo'][j] if state[j] == 1 else P['hi'][j]
        else:
            row = Acsr[j].copy().astype(float)
            gj = -P['q'][j]
            for t in comb.get(j, []):
                sg = np.sign(w[t]) if w[t] != 0 else (-1.0 if state[t] == 2 else 1.0)
                row = row - (1 - theta) * mu[t] * sg * Acsr[t]
                gj += (1 - theta) * mu[t] * sg * P['q'][t]
            E[j, :] = row; g[j] = gj
    E = E.tocsc()
    lu = spl.splu(E)
    x = lu.solve(g)
    for _ in range(2):
        x = x + lu.solve(g - E @ x)
    return x


def run(P, inner=6, tol=1e-9):
    f0, r0, lam = ipm(P)
    fact = f0 if f0 is not None else 60
    theta, step = 0.0, 0.25
    trail = []
    while fact < 400:
        target = min(1.0, theta + step)
        x = lam.copy()
        ok = False
        seen = []
        for _ in range(inner):
            r, state, w = natural(P, x, target)
            if r <= (tol if target == 1.0 else 1e-7):
                ok = True; break
            key = state.tobytes()
            if key in seen: break
            seen.append(key)
            try:
                x = piece_solve(P, x, target, state, w)
            except RuntimeError:
                break
            fact += 1
        if not ok:
            r, _, _ = natural(P, x, target)
            ok = r <= (tol if target == 1.0 else 1e-7)
        if ok:
            lam, theta = x, target
            trail.append(f"{theta:.3g}")
            if theta == 1.0:
                return fact, coupled_residual(P, lam), trail
            step = min(0.5, step * 2)
        else:
            step /= 2
            if step < 1e-3: break
    return None, coupled_residual(P, lam) if theta == 1.0 else natural(P, lam, 1.0)[0], trail


if __name__ == '__main__':
    for path in sys.argv[1:]:
        P = load(path)
        fact, r, trail = run(P)
        print(path.split('/')[-1], P['n'], 'solver', f"{P['res']:.2g}", 'homotopy', fact, f"{r:.2g}", 'thetas', ' '.join(trail), flush=True)
