"""Lemke's method in the pieces of the coupled problem's natural map, from the relaxation's answer.
The relaxation's answer lambda0 is an exact answer of the coupled problem with the normals' free
velocities shifted by -c, c_n = mu sum_t |w_t(lambda0)| (its lift). The path follows the coupled
problem's answer as q(t) = q - (1 - t) c goes from t = 0 to 1: in a fixed piece the answer is
affine in t (one factorisation, two solves); where a row's margin reaches 0 that row changes state
(a pivot), and t moves on in the direction that keeps the new margin non-negative (Lemke's rule,
so t runs backwards where the problem is not monotone). One factorisation a pivot.

Usage: python3 path.py [--snap] [-v] FILES. With --snap the start is moved so that every row's
margin is 1e-8 (relative) instead of the relaxation's answer as it is; -v traces the pivots."""
import sys
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from ccp import load, ipm, coupled_residual
DEBUG = '-v' in sys.argv
DELTA = 1e-8
SNAP = '--snap' in sys.argv

FREE, LOWER, UPPER, CLOSED = 0, 1, 2, 3   # CLOSED: a friction row whose normal is at 0


def initial_state(P, lam, w):
    n, no, mu, d = P['n'], P['no'], P['mu'], P['diag']
    st = np.zeros(n, int)
    sc = max(np.max(np.abs(lam)), 1e-300)
    for j in range(n):
        if no[j] < 0:
            if np.isfinite(P['lo'][j]) and lam[j] - P['lo'][j] <= 1e-9 * sc: st[j] = LOWER
            elif np.isfinite(P['hi'][j]) and P['hi'][j] - lam[j] <= 1e-9 * sc: st[j] = UPPER
    for j in range(n):
        if no[j] < 0: continue
        nn = no[j]
        b = mu[j] * lam[nn]
        if st[nn] != FREE or lam[nn] <= 0: st[j] = CLOSED
        elif lam[j] >= b - 1e-9 * sc: st[j] = UPPER
        elif lam[j] <= -b + 1e-9 * sc: st[j] = LOWER
    return st


def piece(P, st, g_free):
    """E and the right-hand sides (g0, g1) of the piece: E lambda = g0 + t g1."""
    n, no, mu, A = P['n'], P['no'], P['mu'], P['A'].tocsr()
    free = np.array([(st[j] == FREE) for j in range(n)])
    rows, cols, vals = [], [], []
    Af = A[free]
    fi = np.nonzero(free)[0]
    Afc = Af.tocoo()
    rows.extend(fi[Afc.row]); cols.extend(Afc.col); vals.extend(Afc.data)
    g0, g1 = np.zeros(n), np.zeros(n)
    g0[free] = g_free[0][free]; g1[free] = g_free[1][free]
    for j in np.nonzero(~free)[0]:
        rows.append(j); cols.append(j); vals.append(1.0)
        if no[j] >= 0:
            if st[j] in (LOWER, UPPER):
                rows.append(j); cols.append(no[j]); vals.append(mu[j] if st[j] == LOWER else -mu[j])
        else:
            g0[j] = P['lo'][j] if st[j] == LOWER else P['hi'][j]
    E = sp.csc_matrix((vals, (rows, cols)), shape=(n, n))
    return E, g0, g1


def margins(P, st, lam, w):
    """Each row's margin (>= 0 on the path) for its state, as an array; NaN where none."""
    n, no, mu = P['n'], P['no'], P['mu']
    m1 = np.full(n, np.nan); m2 = np.full(n, np.nan)   # two margins for free friction rows
    for j in range(n):
        if no[j] < 0:
            if st[j] == FREE:
                if np.isfinite(P['lo'][j]): m1[j] = lam[j] - P['lo'][j]
                if np.isfinite(P['hi'][j]): m2[j] = P['hi'][j] - lam[j]
            elif st[j] == LOWER: m1[j] = w[j]
            else: m1[j] = -w[j]
        else:
            b = mu[j] * lam[no[j]]
            if st[j] == FREE: m1[j] = b - lam[j]; m2[j] = lam[j] + b
            elif st[j] == UPPER: m1[j] = -w[j]
            elif st[j] == LOWER: m1[j] = w[j]
    return m1, m2


def lift(P, w):
    """The relaxation's lift on the normals, mu sum_t |w_t|: with q lowered by it, the relaxation's
    answer is itself the coupled problem's answer at t = 0."""
    c = np.zeros(P['n'])
    fr = np.nonzero(P['no'] >= 0)[0]
    np.add.at(c, P['no'][fr], P['mu'][fr] * np.abs(w[fr]))
    return c


def snapped_offset(P, lam0, st):
    """--snap: the offset of a start with every margin strictly positive (no zero-length pivots at
    t = 0): the state's fixed and tied equations met exactly, free rows DELTA inside their bounds,
    and at t = 0 free rows with w = 0 and the others with w DELTA outward."""
    no, mu, q = P['no'], P['mu'], P['q']
    lam = lam0.copy()
    dl = DELTA * max(np.max(np.abs(lam0)), 1e-300)
    dw = DELTA * max(np.max(np.abs(q)), 1e-300)
    for j in range(P['n']):
        if no[j] >= 0: continue
        if st[j] == LOWER: lam[j] = P['lo'][j]
        elif st[j] == UPPER: lam[j] = P['hi'][j]
        else:
            if np.isfinite(P['lo'][j]): lam[j] = max(lam[j], P['lo'][j] + dl)
            if np.isfinite(P['hi'][j]): lam[j] = min(lam[j], P['hi'][j] - dl)
    for j in range(P['n']):
        if no[j] < 0: continue
        b = mu[j] * lam[no[j]]
        if st[j] == CLOSED: lam[j] = 0
        elif st[j] == UPPER: lam[j] = b
        elif st[j] == LOWER: lam[j] = -b
        else: lam[j] = np.clip(lam[j], -b + min(dl, 0.5 * b), b - min(dl, 0.5 * b))
    out = np.where(st == LOWER, dw, np.where(st == UPPER, -dw, 0.0))
    c = P['A'] @ lam + q - out
    c[st == CLOSED] = 0
    return c


def run(P, max_pivots=300):
    f0, r0, lam0 = ipm(P)
    fact = f0 if f0 is not None else 60
    q = P['q'].copy()
    w0 = P['A'] @ lam0 + q
    st = initial_state(P, lam0, w0)
    c = snapped_offset(P, lam0, st) if SNAP else lift(P, w0)
    t, direction = 0.0, 1.0
    gq0, gq1 = -(q - c), -c          # free rows: A lambda = -(q - c) - t c
    last_changed = None
    for pivot in range(max_pivots):
        E, g0, g1 = piece(P, st, (gq0, gq1))
        try:
            lu = spl.splu(E)
        except RuntimeError:
            return None, fact, 'singular', t
        fact += 1
        a = lu.solve(g0); b = lu.solve(g1)
        if DEBUG and pivot > 0:
            jump = np.max(np.abs(a + t * b - prev)) / max(np.max(np.abs(prev)), 1e-300)
            print(f"  pivot {pivot} t {t:.6g} dir {direction:+.0f} row {last_changed} state {st[last_changed[0]]} normal_of {P['no'][last_changed[0]]} jump {jump:.2g}")
        # w(t) = A lambda(t) + q - (1 - t) c = (A a + q - c) + t (A b + c)
        wa = P['A'] @ a + q - c; wb = P['A'] @ b + c
        ma1, ma2 = margins(P, st, a, wa)
        mb1, mb2 = margins(P, st, b, wb)
        # margins are affine in lambda and w for the given state: m(t) = m(a) + t (m(b) - m(0))
        z = np.zeros(P['n'])
        m01, m02 = margins(P, st, z, np.zeros(P['n']) + 0.0)
        # constant parts: for lam - lo, m(0 point) = -lo etc.; slope = m(b-point) - m(zero point)
        s1 = mb1 - m01; s2 = mb2 - m02
        if last_changed is not None:
            j, which = last_changed
            slope = (s1 if which == 1 else s2)[j]
            direction = 1.0 if slope > 0 else -1.0 if slope < 0 else direction
        best_dt, hit = np.inf, None
        for arr_m, arr_s, which in ((ma1, s1, 1), (ma2, s2, 2)):
            val = arr_m + t * arr_s   # margin now
            rate = arr_s * direction
            ok = np.isfinite(val) & (rate < 0)
            if last_changed is not None:
                ok[last_changed[0]] = ok[last_changed[0]] & (which != last_changed[1])
            if not ok.any(): continue
            dts = np.maximum(val[ok], 0) / -rate[ok]
            k = np.argmin(dts)
            if dts[k] < best_dt:
                best_dt, hit = dts[k], (np.nonzero(ok)[0][k], which)
        if direction > 0 and t + best_dt >= 1.0:
            lam = a + b
            return pivot, fact, coupled_residual(P, lam), 1.0
        if hit is None:
            return None, fact, 'ray', t
        t = t + direction * best_dt
        j, which = hit
        prev = a + t * b
        # pivot: row j changes state
        w_t = wa + t * wb
        if P['no'][j] < 0:
            if st[j] == FREE:
                st[j] = LOWER if which == 1 else UPPER
                new_which = 1
                if P['lo'][j] == 0 and which == 1:   # a normal closing: its friction rows close
                    for k in np.nonzero(P['no'] == j)[0]: st[k] = CLOSED
            else:
                was_normal_closed = st[j] == LOWER and P['lo'][j] == 0
                st[j] = FREE
                new_which = 1 if np.isfinite(P['lo'][j]) else 2
                if was_normal_closed:  # its friction rows take the side their sliding asks for
                    for k in np.nonzero(P['no'] == j)[0]:
                        st[k] = LOWER if w_t[k] > 0 else UPPER if w_t[k] < 0 else FREE
                new_which = 1
        else:
            if st[j] == FREE:
                st[j] = UPPER if which == 1 else LOWER
                new_which = 1
            else:
                new_which = 1 if st[j] == UPPER else 2
                st[j] = FREE
        last_changed = (j, new_which)
    return None, fact, 'budget', t


if __name__ == '__main__':
    for path in [a for a in sys.argv[1:] if a not in ('-v', '--snap')]:
        P = load(path)
        piv, fact, r, t = run(P)
        print(path.split('/')[-1], P['n'], 'solver', f"{P['res']:.2g}", 'path pivots', piv, 'factorisations', fact, 'end', r if isinstance(r, str) else f"{r:.2g}", f"t {t:.3g}", flush=True)
