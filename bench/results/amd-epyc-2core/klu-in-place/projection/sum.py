import csv, statistics as st, sys
tags = sys.argv[1:]
for t in tags:
    rows = []
    for s in range(1, 6):
        r = list(csv.DictReader(open(f'{t}_{s}.csv')))
        pen = max(float(x['max_penetration']) for x in r) * 1000
        uns = sum(int(x['unsettled']) > 0 for x in r)
        last = st.median(float(x['solve_ms']) for x in r[-100:])
        tot = sum(float(x['total_ms']) for x in r) / 1000
        proj = sum(float(x['project_ms']) for x in r) / 1000
        ke = float(r[-1]['kinetic_energy'])
        rows.append((pen, uns, last, ke, tot, proj))
    print(f"{t:8s} pen mm " + " ".join(f"{p[0]:.2f}" for p in rows) + " | unsettled " + " ".join(str(p[1]) for p in rows)
          + " | last100 solve " + " ".join(f"{p[2]:.1f}" for p in rows) + " | KE " + " ".join(f"{p[3]:.2g}" for p in rows)
          + " | total s " + " ".join(f"{p[4]:.1f}" for p in rows) + " | project s " + " ".join(f"{p[5]:.2f}" for p in rows))
