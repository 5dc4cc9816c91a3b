"""Lemke's method from zero on the Stewart-Trinkle LCP of the dumped stalled islands.

Usage: python3 lemke_small.py DIR   (DIR: where stalled_small_islands.tar.gz was unpacked, 0.txt ...)
Prints, per island: rows, bodies, Lemke's pivots and end (ok / ray), the natural map's residual
of its answer (the solver's scaling), and the answer's rows by state."""
import sys
import numpy as np
from collections import Counter
from pathlib import Path

from load import lcp, lemke, load, residual
from states import classify, natural_state, strictness

for path in sorted(Path(sys.argv[1]).glob("*.txt"), key=lambda p: int(p.stem)):
    P = load(str(path))
    M, qq, E = lcp(P)
    z, pivots = lemke(M, qq)
    end = 'ok' if z is not None else 'ray'
    line = f"{path.name}: {P['n']} rows, {P['b']} bodies, warm start {residual(P, P['warm']):.3g}; Lemke {end} after {pivots} pivots"
    if z is not None:
        lam = E @ z
        line += f", residual {residual(P, lam):.3g}, strictness {strictness(P, lam):.2g}, states {dict(Counter(classify(P, lam)))}"
    print(line)
    if z is not None and P['best'] is not None:
        a, b = natural_state(P, lam), natural_state(P, P['best'])
        print(f"    the solver's best iterate (residual {residual(P, P['best']):.3g}) lies in another piece of the natural map than the answer on "
              f"{sum(x != y for x, y in zip(a, b))} of {P['n']} rows, impulses by up to "
              f"{np.max(np.abs(P['best'] - lam)) / max(np.max(np.abs(lam)), 1e-300):.2g} of the largest")
