# The convex relaxation of an island's coupled problem (friction in its pyramid) as a dense QP,
# min 1/2 x'Ax + c'x subject to G x <= h, and Mehrotra's interior-point steps on it.
import os, sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "wedged_island"))
import numpy as np

def constraints(n, lo, hi, nof, mu):
    """G, h: |lambda_t| <= mu lambda_n for friction rows, the bounds of the others."""
    G = []; h = []
    for j in range(n):
        if nof[j] >= 0:
            for s in (1, -1):
                g = np.zeros(n); g[j] = s; g[nof[j]] = -mu[j]; G.append(g); h.append(0.)
        else:
            if np.isfinite(lo[j]): g = np.zeros(n); g[j] = -1; G.append(g); h.append(-lo[j])
            if np.isfinite(hi[j]): g = np.zeros(n); g[j] = 1; G.append(g); h.append(hi[j])
    return np.array(G), np.array(h)

def desaxce_shift(q, w, nof, mu):
    """q with each normal's free velocity raised by mu |w_t| of its friction rows."""
    c = q.copy()
    for j in range(len(q)):
        if nof[j] >= 0: c[nof[j]] += mu[j] * abs(w[j])
    return c

def start(A, G):
    return np.zeros(A.shape[0]), np.ones(G.shape[0]), np.ones(G.shape[0])

def mehrotra_step(A, c, G, h, x, s, z):
    """One predictor-corrector step from (x, slacks s, multipliers z), in place; False if its
    system is singular."""
    m = len(h)
    rd = A @ x + c + G.T @ z; rp = G @ x + s - h; gap = s @ z / m
    K = A + G.T @ np.diag(z / s) @ G
    def solve(rc):
        rhs = -rd - G.T @ ((z * rp - rc) / s); dx = np.linalg.solve(K, rhs); ds = -rp - G @ dx
        return dx, ds, (-rc - z * ds) / s
    def to_boundary(v, dv):
        neg = dv < 0
        return min(1, np.min(-v[neg] / dv[neg])) if neg.any() else 1.0
    try:
        dx, ds, dz = solve(s * z)
        a = min(to_boundary(s, ds), to_boundary(z, dz))
        sigma = (((s + a * ds) @ (z + a * dz) / m) / gap) ** 3
        dx, ds, dz = solve(s * z + ds * dz - sigma * gap)
    except np.linalg.LinAlgError:
        return False
    a = min(1, 0.99 * min(to_boundary(s, ds), to_boundary(z, dz)))
    x += a * dx; s += a * ds; z += a * dz
    return True

def ipm(A, c, G, h, tol=1e-15, iters=200):
    """The QP solved until the mean complementarity is tol max(1, |c|); x, s, z, steps."""
    x, s, z = start(A, G)
    for it in range(iters):
        if s @ z / len(h) < tol * max(1, np.abs(c).max()) or not mehrotra_step(A, c, G, h, x, s, z): break
    return x, s, z, it
