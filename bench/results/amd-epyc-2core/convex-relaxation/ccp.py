"""The convex relaxation (CCP) of an island's coupled box-friction problem,
min 1/2 l'Al + q'l s.t. normals >= 0, |l_t| <= mu l_n (linear), joint bounds, solved by Mehrotra's
predictor-corrector on its row-space system with the multipliers kept (AugmentedSolver). Counts
factorisations to its own residual <= 1e-9 (velocity units / max|q|)."""
import sys
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl


def load(path):
    with open(path) as f:
        head = f.readline().split()
        n, b, settled, fact, res = int(head[0]), int(head[1]), int(head[2]), int(head[3]), float(head[4])
        B = np.loadtxt(f, max_rows=b, ndmin=2) if b else np.zeros((0, 10))
        R = np.loadtxt(f, max_rows=n, ndmin=2)
    P = dict(n=n, b=b, settled=settled, fact=fact, res=res)
    P['q'], P['lo'], P['hi'], P['sigma'] = R[:, 0], R[:, 1], R[:, 2], R[:, 3]
    P['no'] = R[:, 4].astype(int)
    P['mu'], P['diag'] = R[:, 5], R[:, 6]
    bod = R[:, 7:9].astype(int)
    jac = R[:, 9:21].reshape(n, 2, 6)
    rows, cols, vals = [], [], []
    for slot in range(2):
        ok = bod[:, slot] >= 0
        for c in range(6):
            rows.append(np.nonzero(ok)[0]); cols.append(6 * bod[ok, slot] + c); vals.append(jac[ok, slot, c])
    J = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, 6 * b))
    blocks = []
    for k in range(b):
        m = np.zeros((6, 6)); m[:3, :3] = B[k, 0] * np.eye(3); m[3:, 3:] = B[k, 1:10].reshape(3, 3)
        blocks.append(m)
    Minv = sp.block_diag(blocks, format='csr') if b else sp.csr_matrix((0, 0))
    if R.shape[1] > 21:   # a dump with the warm start (rest.py)
        P['warm'], P['warm_state'] = R[:, 21], R[:, 22].astype(int)
    P['A'] = (J @ Minv @ J.T + sp.diags(P['sigma'])).tocsr()
    return P


def constraints(P):
    """G (sparse, constraints x rows) and c: G l - c >= 0. Friction rows with mu = 0 and closed
    rows are held at 0 / their bound by a pair of constraints only if they have an interior."""
    n, no, mu, lo, hi = P['n'], P['no'], P['mu'], P['lo'], P['hi']
    r, cidx, v, c, row_of = [], [], [], [], []
    k = 0
    for j in range(n):
        if no[j] >= 0:
            for sgn in (1, -1):
                r += [k, k]; cidx += [j, no[j]]; v += [sgn, mu[j]]; c.append(0.0); row_of.append(j); k += 1
        else:
            if np.isfinite(lo[j]):
                r.append(k); cidx.append(j); v.append(1.0); c.append(lo[j]); row_of.append(j); k += 1
            if np.isfinite(hi[j]):
                r.append(k); cidx.append(j); v.append(-1.0); c.append(-hi[j]); row_of.append(j); k += 1
    G = sp.csr_matrix((v, (r, cidx)), shape=(k, n))
    return G, np.array(c), np.array(row_of, dtype=int)


class AugmentedSolver:
    """The step's system in row space, multipliers kept: [[A, -G'], [G, S/Z]] (no huge entries
    on active constraints, so no digits lost there); sparse LU."""

    def __init__(self, P, G):
        self.P, self.G = P, G
        self.n, self.m = P['n'], G.shape[0]

    def factor(self, Dinv):
        self.Dinv = Dinv
        K = sp.bmat([[self.P['A'], -self.G.T], [self.G, sp.diags(Dinv)]], format='csc')
        self.K = K
        self.lu = spl.splu(K)

    def solve(self, r1, r2):
        r = np.concatenate([r1, r2])
        x = self.lu.solve(r)
        for _ in range(2):
            e = r - self.K @ x
            if np.max(np.abs(e)) <= 1e-16 * max(np.max(np.abs(r)), 1e-300): break
            x = x + self.lu.solve(e)
        return x[:self.n], x[self.n:]


def residual(P, G, c, row_of, lam, z):
    """The relaxation's KKT error in velocity units / max|q|: stationarity per row, and per
    constraint min(A_jj * slack, z) and A_jj * infeasibility."""
    scale = max(np.max(np.abs(P['q'])), 1e-12)
    w = P['A'] @ lam + P['q']
    stat = np.abs(w - G.T @ z)
    s = G @ lam - c
    d = P['diag'][row_of]
    comp = np.minimum(np.abs(d * s), np.abs(z))
    infeas = d * np.maximum(0, -s)
    return max(stat.max(initial=0), comp.max(initial=0), infeas.max(initial=0)) / scale


def states(P, G, c, row_of, lam, s, z):
    """Each row's piece from the iterate: constraints whose multiplier exceeds A_jj * slack are
    active. Per row: 'F' free, 'L' / 'U' at a bound given as a number (a friction row of a closed
    contact at 0), 'TL' / 'TU' tied to -+mu lambda_n."""
    d = P['diag'][row_of]
    act = z > d * s
    st = ['F'] * P['n']
    first = {}
    for k, j in enumerate(row_of):
        first.setdefault(j, []).append(k)
    for j in range(P['n']):
        if P['no'][j] >= 0: continue
        ks = first.get(j, [])
        for k in ks:
            if act[k]: st[j] = 'L' if G[k, j] > 0 else 'U'
    for j in range(P['n']):
        n = P['no'][j]
        if n < 0: continue
        klo, khi = first[j]
        if st[n] != 'F': st[j] = 'L'   # closed contact: lambda_t = 0
        elif act[klo] and z[klo] - d[klo] * s[klo] >= z[khi] - d[khi] * s[khi]: st[j] = 'TL'
        elif act[khi]: st[j] = 'TU'
    return st


def finish(P, st):
    """The equality-constrained QP of the piece st, solved exactly (sparse LU of its KKT system)."""
    n = P['n']
    r, cc, v, rhs = [], [], [], []
    k = 0
    for j in range(n):
        if st[j] in ('L', 'U'):
            val = 0.0 if P['no'][j] >= 0 else (P['lo'][j] if st[j] == 'L' else P['hi'][j])
            r.append(k); cc.append(j); v.append(1.0); rhs.append(val); k += 1
        elif st[j] in ('TL', 'TU'):
            sg = 1.0 if st[j] == 'TL' else -1.0   # TL: l_t + mu l_n = 0; TU: -l_t + mu l_n = 0
            r += [k, k]; cc += [j, P['no'][j]]; v += [sg, P['mu'][j]]; rhs.append(0.0); k += 1
    C = sp.csr_matrix((v, (r, cc)), shape=(k, n))
    K = sp.bmat([[P['A'], C.T], [C, None]], format='csc')
    b = np.concatenate([-P['q'], rhs])
    lu = spl.splu(K)
    x = lu.solve(b)
    for _ in range(2):
        x = x + lu.solve(b - K @ x)
    return x[:n]


def point_residual(P, lam):
    """The relaxation's residual at a primal point: each friction row's multipliers chosen from its
    place in its box (interior: none; at an edge: the outward part of w_t; closed contact: |w_t|),
    their pull mu (z_lo + z_hi) moved to the normal, whose natural map is then measured; and any
    friction outside its box."""
    scale = max(np.max(np.abs(P['q'])), 1e-12)
    w = P['A'] @ lam + P['q']
    d = P['diag']
    err = np.zeros(P['n'])
    pull = np.zeros(P['n'])
    tol = 1e-12
    for j in range(P['n']):
        n = P['no'][j]
        if n < 0: continue
        b = P['mu'][j] * max(lam[n], 0.0)
        if lam[n] <= 0:
            zl, zh = max(w[j], 0), max(-w[j], 0); err[j] = 0
        elif lam[j] >= b * (1 - tol):
            zl, zh = 0, max(-w[j], 0); err[j] = max(w[j], 0)
        elif lam[j] <= -b * (1 - tol):
            zl, zh = max(w[j], 0), 0; err[j] = max(-w[j], 0)
        else:
            zl = zh = 0; err[j] = abs(w[j])
        err[j] = max(err[j], d[j] * max(0, abs(lam[j]) - b))
        pull[n] += P['mu'][j] * (zl + zh)
    for j in range(P['n']):
        if P['no'][j] >= 0: continue
        wh = w[j] - pull[j]
        err[j] = abs(lam[j] - np.clip(lam[j] - wh / d[j], P['lo'][j], P['hi'][j])) * d[j]
    return np.max(err) / scale


def natural(P, lam, theta=1.0):
    """Residual (solver's scaling), state (0 free, 1 lower, 2 upper) and w of P(theta) at lam: the
    normals' complementarity on w_n - (1 - theta) mu sum_t |w_t| (theta = 0 the relaxation,
    1 the coupled problem of DESIGN.md section 3; homotopy.py)."""
    w = P['A'] @ lam + P['q']
    wh = w.copy()
    f = P['no'] >= 0
    fr = np.nonzero(f)[0]
    np.subtract.at(wh, P['no'][fr], (1 - theta) * P['mu'][fr] * np.abs(w[fr]))
    lo, hi = P['lo'].copy(), P['hi'].copy()
    hi[f] = P['mu'][f] * np.maximum(0, lam[P['no'][f]]); lo[f] = -hi[f]
    x = lam - np.where(f, w, wh) / P['diag']     # friction rows: w_t; normals and joints: shifted
    F = (lam - np.clip(x, lo, np.maximum(lo, hi))) * P['diag']
    state = np.where(x <= lo, 1, np.where(x >= hi, 2, 0))
    return np.max(np.abs(F)) / max(np.max(np.abs(P['q'])), 1e-12), state, w


def coupled_residual(P, lam):
    return natural(P, lam, 1.0)[0]


def ipm(P, budget=60, tol=1e-9, trace=False):
    G, c, row_of = constraints(P)
    n, m = P['n'], G.shape[0]
    scale = max(np.max(np.abs(P['q'])), 1e-12)
    lam = np.zeros(n)
    d = P['diag'][row_of]
    s = np.maximum(G @ lam - c, 0) + 0.1 * scale / d
    z = np.full(m, 0.1 * scale)
    solver = AugmentedSolver(P, G)
    if point_residual(P, lam) <= tol:   # no push anywhere: lambda = 0 is the answer
        return 0, point_residual(P, lam), lam
    best = (np.inf, lam)
    factorizations = 0
    gap0 = None
    last_state = None
    for it in range(1, budget + 1):
        if factorizations >= budget: break
        w = P['A'] @ lam + P['q']
        rd = w - G.T @ z
        rp = G @ lam - c - s
        gap = s @ z / max(m, 1)
        gap0 = gap0 or gap
        if not gap > 0: break
        try:
            solver.factor(s / z)
        except RuntimeError:
            break
        factorizations += 1
        def direction(target):
            # A dl - G' dz = -rd;  G dl + (S/Z) dz = (target - Z rp) / z
            dl, dz = solver.solve(-rd, (target - z * rp) / z)
            ds = G @ dl + rp
            return dl, ds, dz
        def longest(s_, ds_, z_, dz_):
            a = 1.0
            neg = ds_ < 0
            if neg.any(): a = min(a, np.min(-s_[neg] / ds_[neg]))
            neg = dz_ < 0
            if neg.any(): a = min(a, np.min(-z_[neg] / dz_[neg]))
            return a
        dl, ds, dz = direction(-s * z)
        aff = longest(s, ds, z, dz)
        gap_aff = (s + aff * ds) @ (z + aff * dz) / max(m, 1)
        tau = (gap_aff / gap) ** 3 * gap if gap > 0 else 0
        dl2, ds2, dz2 = direction(-s * z + tau - ds * dz)
        a = min(1.0, 0.99 * longest(s, ds2, z, dz2))
        lam = lam + a * dl2; s = s + a * ds2; z = z + a * dz2
        r = residual(P, G, c, row_of, lam, z)
        if r < best[0]: best = (r, lam.copy())
        if trace: print(it, f"alpha {a:.3g} gap {gap:.3g} res {r:.3g}")
        if r <= tol:
            return factorizations, r, lam
        # Near the answer, one exact solve in the piece the iterate indicates (one factorisation).
        st = states(P, G, c, row_of, lam, s, z) if r < 1e-5 else None
        if st is not None and st != last_state and factorizations < budget:
            last_state = st
            factorizations += 1
            try:
                x = finish(P, st)
            except RuntimeError:
                continue
            rf = point_residual(P, x)
            if trace: print('  finish', f"{rf:.3g}")
            if rf < best[0]: best = (rf, x)
            if rf <= tol:
                return factorizations, rf, x
    return None, best[0], best[1]


if __name__ == '__main__':
    for path in [a for a in sys.argv[1:] if a != '-v']:
        P = load(path)
        try:
            it, r, lam = ipm(P, trace='-v' in sys.argv)
        except RuntimeError as e:
            print(path, P['n'], P['b'], 'solver', P['settled'], P['fact'], f"{P['res']:.2g}", 'ccp', 'failed', str(e).replace(' ', '_'), 'coupled', 'nan')
            continue
        w = P['A'] @ lam + P['q']
        loaded = (P['no'] < 0) & (P['lo'] == 0) & (lam > 0)
        lift = max(w[loaded].max(initial=0.0), 0.0)   # m/s: a loaded contact separating
        print(path, P['n'], P['b'], 'solver', P['settled'], P['fact'], f"{P['res']:.2g}", 'ccp', it, f"{r:.2g}", 'coupled', f"{coupled_residual(P, lam):.2g}", 'lift', f"{lift:.2g}", 'maxq', f"{np.max(np.abs(P['q'])):.2g}", flush=True)
