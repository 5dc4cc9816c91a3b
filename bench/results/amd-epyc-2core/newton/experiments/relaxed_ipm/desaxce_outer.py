# De Saxce's fixed point with exact QPs: solve the relaxed QP, shift the normals by mu |w_t| of its
# answer, repeat; prints each QP's KKT residual and the coupled problem's residual of its answer.
# Usage: desaxce_outer.py ISLAND.txt (the format of ../wedged_island/blcp.py)
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np
from qp import constraints, desaxce_shift, ipm
from blcp import load, resid

A, q, lo, hi, nof, mu, warm, ans = load(sys.argv[1])
G, h = constraints(len(q), lo, hi, nof, mu)
c = q
for k in range(25):
    x, s, z, it = ipm(A, c, G, h)
    rd = A @ x + c + G.T @ z
    print(k, 'ipm its', it, 'KKT rd %.1e' % np.abs(rd).max(), 'gap %.1e' % (s @ z / len(h)),
          'coupled %.2e' % resid(A, q, x, lo, hi, nof, mu))
    c = desaxce_shift(q, A @ x + q, nof, mu)
