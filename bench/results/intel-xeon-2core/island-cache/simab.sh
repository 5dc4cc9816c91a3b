# simulate A/B from the resting LRP state: old (/tmp/wt) vs new; solve ms summed over steps 2..N
runs=$1; shift
for i in $(seq $runs); do
for b in /tmp/wt/build/rbpart /work/main/build/rbpart; do
  $b simulate --scene large_rock_pile --initial-state /tmp/s27/lrp300.json "$@" --stats /tmp/s27/simab.csv -q
  python3 -c "
import csv;r=list(csv.DictReader(open('/tmp/s27/simab.csv')))[1:];print('$b'.split('/')[2], round(sum(float(x['solve_ms']) for x in r)/len(r),2), round(sum(float(x['critical_path_ms']) for x in r)/len(r),2), round(sum(float(x['work_ms']) for x in r)/len(r),2))"
done; done
