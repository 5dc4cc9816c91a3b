"""Bins of run.sh: per build, runs above 1 J at the end, boxes below the floor, medians. Usage: bins_summary.py OUT"""
import sys
import csv, json, glob, statistics
rows = {}
def one(csvf, statef):
    r = list(csv.DictReader(open(csvf))); st = json.load(open(statef))
    bodies = st['bodies'] if 'bodies' in st else st
    below = sum(1 for b in bodies if b.get('name') != 'floor' and b['position'][2] < 0)
    return (float(r[-1]['kinetic_energy']), sum(float(x['unsettled']) > 0 for x in r), below, 1000 * max(float(x['max_penetration']) for x in r), sum(float(x['solve_ms']) for x in r) / 1000)
for T in ('base', 'prox'):
    res = []
    for S in range(1, 16):
        c = f'{sys.argv[1]}/bins/{T}_{S}.csv'
        try: res.append(one(c, c[:-4] + '.state.json'))
        except Exception as e: pass
    print(T, 'n', len(res), 'KE>1J', sum(x[0] > 1 for x in res), 'below floor total', sum(x[2] for x in res), 'seeds with any below', sum(x[2] > 0 for x in res),
          'unsettled median', statistics.median(x[1] for x in res), 'maxpen median %.0f mm' % statistics.median(x[3] for x in res), 'solve median %.1f s' % statistics.median(x[4] for x in res))
