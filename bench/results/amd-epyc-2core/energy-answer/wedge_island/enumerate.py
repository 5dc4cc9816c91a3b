"""Every solution of the dumped island's coupled problem, by trying every combination of contact
states (separating, or pressing with each friction row free or at -+mu lambda_n); prints those whose
residual (DESIGN.md section 3) is below 1e-6, and the residual of the solver's answer.
Usage: /usr/bin/python3 enumerate.py island.txt"""
import itertools, sys
import numpy as np


def load(path):
    lines = open(path).read().split('\n')
    n = int(lines[0])
    a = np.array([[float(x) for x in lines[1 + i].split()] for i in range(n)])
    r = np.array([[float(x) for x in lines[1 + n + i].split()] for i in range(n)])
    return dict(A=a, q=r[:, 0], lo=r[:, 1], hi=r[:, 2], mu=r[:, 3], normal_of=r[:, 4].astype(int),
                start=r[:, 5], best=r[:, 6])


def residual(p, lam):
    a, q = p['A'], p['q']
    w = a @ lam + q
    d = np.diag(a)
    lo, hi = p['lo'].copy(), p['hi'].copy()
    for j, nj in enumerate(p['normal_of']):
        if nj >= 0:
            hi[j] = p['mu'][j] * max(0, lam[nj])
            lo[j] = -hi[j]
    f = (lam - np.clip(lam - w / d, lo, np.maximum(lo, hi))) * d
    return np.abs(f).max() / max(np.abs(q).max(), 1e-12)


p = load(sys.argv[1])
a, q, no, mu = p['A'], p['q'], p['normal_of'], p['mu']
n = len(a)
normals = [j for j in range(n) if no[j] < 0]
tangents = {nj: [j for j in range(n) if no[j] == nj] for nj in normals}
states = [None] + list(itertools.product([0, 1, -1], repeat=2))
print('warm start residual %.3g, solver answer %.3g' % (residual(p, p['start']), residual(p, p['best'])))
for combo in itertools.product(states, repeat=len(normals)):
    e, g = np.zeros((n, n)), np.zeros(n)
    for nj, st in zip(normals, combo):
        if st is None:
            e[nj, nj] = 1
            for j in tangents[nj]:
                e[j, j] = 1
            continue
        e[nj], g[nj] = a[nj], -q[nj]
        for j, s in zip(tangents[nj], st):
            if s == 0:
                e[j], g[j] = a[j], -q[j]
            else:
                e[j, j], e[j, nj] = 1, -s * mu[j]
    try:
        lam = np.linalg.solve(e, g)
    except np.linalg.LinAlgError:
        continue
    r = residual(p, lam)
    if r < 1e-6:
        print('solution, residual %.2g, states %s' % (r, combo))
        print('  lambda', np.round(lam, 4))
