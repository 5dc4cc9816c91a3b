# Prints each table1.csv's substructured rows against its direct solve: the mean solve and its
# ratio at the run's threads, work, critical path, the 16-core estimate and its ratio, the
# partition + refine share, interface bodies. Usage: python3 compare.py TABLE1.csv ...
import csv
import sys

for path in sys.argv[1:]:
    rows = list(csv.DictReader(open(path)))
    for scene in sorted({r['scene'] for r in rows}):
        own = [r for r in rows if r['scene'] == scene]
        direct = float(next(r for r in own if r['solver'].startswith('direct'))['mean_solve_ms'])
        print(f'{path} {scene}: direct {direct:.2f} ms')
        for r in own:
            if r['solver'].startswith('direct'):
                continue
            mean = float(r['mean_solve_ms'])
            share = 100 * (float(r['mean_partition_ms']) + float(r['mean_refine_ms'])) / mean
            print(f"  {r['partitioner']} n_max {r['nmax']}: {mean:.2f} ms ({direct / mean:.2f}x), "
                  f"work {float(r['mean_work_ms']):.2f}, critical path {float(r['mean_critical_path_ms']):.2f}, "
                  f"16 cores {float(r['mean_est16_ms']):.2f} ms ({float(r['est16_speedup_vs_direct']):.2f}x), "
                  f"partition + refine {share:.2f} %, interface bodies {float(r['mean_interface_bodies']):.1f}")
