# Factorisations per island and per step, from the stats CSVs of seeds.sh (plus cur_chain_1.csv, cur_log_1.csv).
# Usage: python3 island_summary.py DIR
import csv, glob, statistics as st, sys, collections, os
D = sys.argv[1]
by = collections.defaultdict(list)
for f in sorted(glob.glob(D + '/cur_*.csv')):
    name = os.path.basename(f).split('_')[1]
    r = list(csv.DictReader(open(f)))
    last = r[-100:]
    by[name].append(dict(
        imax=max(int(x['island_factorizations']) for x in r),
        irest=st.median(int(x['island_factorizations']) for x in last),
        irest_max=max(int(x['island_factorizations']) for x in last),
        smax=max(int(x['factorizations']) for x in r),
        srest=st.median(int(x['factorizations']) for x in last),
        islands=st.median(int(x['islands']) for x in last),
        at_budget=sum(int(x['island_factorizations']) >= 40 for x in r),
        uns=sum(int(x['unsettled']) > 0 for x in r)))
for name, v in by.items():
    med = lambda k: st.median(x[k] for x in v)
    print(f"{name:6s} n={len(v)} island max {max(x['imax'] for x in v)}  island median at rest {med('irest')} (max in last 100: {max(x['irest_max'] for x in v)})  "
          f"step sum max {max(x['smax'] for x in v)} median at rest {med('srest')} over {med('islands')} islands  steps with an island at the budget {med('at_budget')}  unsettled {med('uns')}")
