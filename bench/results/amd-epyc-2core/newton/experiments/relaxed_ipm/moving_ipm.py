# The relaxed QP's interior-point steps with de Saxce's shift taken from each iterate (one run);
# prints the steps taken and the coupled residual reached, per island file.
# Usage: moving_ipm.py ISLAND.txt ... (the format of ../wedged_island/blcp.py)
import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from qp import constraints, desaxce_shift, mehrotra_step, start
from blcp import load, resid

def moving(A, q, lo, hi, nof, mu, G, h, iters=60):
    x, s, z = start(A, G)
    for it in range(iters):
        r = resid(A, q, x, lo, hi, nof, mu)
        if r < 1e-10 or not mehrotra_step(A, desaxce_shift(q, A @ x + q, nof, mu), G, h, x, s, z): break
    return it, r

for f in sys.argv[1:]:
    A, q, lo, hi, nof, mu, warm, ans = load(f)
    G, h = constraints(len(q), lo, hi, nof, mu)
    print(f, len(q), 'moving IPM it %d res %.2e' % moving(A, q, lo, hi, nof, mu, G, h))
