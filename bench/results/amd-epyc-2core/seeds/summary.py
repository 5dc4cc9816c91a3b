"""Median and range over seeds of seeds.sh's runs: summary.py OUT TAG..."""
import csv, glob, statistics, sys

out = sys.argv[1]
for tag in sys.argv[2:]:
    for name in ['rock', 'bp', 'hard', 'large']:
        rows = []
        for path in sorted(glob.glob(f'{out}/{tag}_{name}_*.csv')):
            r = list(csv.DictReader(open(path)))
            f = sorted(float(x['factorizations']) for x in r)
            s = [float(x['solve_ms']) for x in r]
            last = sorted(s[-100:])
            rows.append((sum(float(x['unsettled']) > 0 for x in r), sum(s) / 1000,
                         f[len(f) // 2], f[-1], float(r[-1]['kinetic_energy']),
                         1000 * max(float(x['max_penetration']) for x in r), len(r), max(s), last[len(last) // 2],
                         100 * sum(float(x['factor_ms']) for x in r) / max(sum(s), 1e-9)))
        if not rows:
            continue
        def col(k, fmt):
            v = [x[k] for x in rows]
            return f"{fmt % statistics.median(v)} ({fmt % min(v)}-{fmt % max(v)})"
        print(f"{tag:8} {name:6} seeds {len(rows)} steps {rows[0][6]}: unsettled {col(0, '%d')}  solve s {col(1, '%.1f')}"
              f"  slowest ms {col(7, '%.0f')}  last-100 median ms {col(8, '%.1f')}"
              f"  fact/step med {col(2, '%d')} max {col(3, '%d')}  factorising % of solve {col(9, '%.0f')}"
              f"  KE J {col(4, '%.1e')}  pen mm {col(5, '%.1f')}")
