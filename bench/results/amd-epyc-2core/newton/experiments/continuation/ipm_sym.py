# The interior point of ../wedged_island/ipm.py with the symmetric (associated) matrix on stalls:
# ipm_sym.py ISLAND.txt...  (islands as ../wedged_island/blcp.py reads them)
import sys, os
sys.path.insert(0, os.path.join(os.path.dirname(__file__), '..', 'wedged_island'))
from blcp import load
from ipm import ipm
for f in sys.argv[1:]:
    A,q,lo,hi,nof,mu,warm,ans=load(f)
    for sy in [0,0.01,0.1,1]:
        print(f, sy, ipm(A,q,lo,hi,nof,mu,mehrotra=True,iters=80,symm=sy))
