# Deepest penetration and steps starting deeper than 2 mm, per seed, from the seeds.sh runs.
# Usage: penetration.py OUT SCENES TAG...   e.g. penetration.py /tmp/seeds rock,bp,hard,large cur r6
import csv, glob, sys, numpy as np
d=sys.argv[1]
for scene in sys.argv[2].split(','):
  for tag in sys.argv[3:]:
    out=[]
    for f in sorted(glob.glob(f'{d}/{tag}_{scene}_*.csv')):
      r=list(csv.DictReader(open(f)))
      p=np.array([float(x['max_penetration'])*1000 for x in r]); pm=sum(float(x['project_ms']) for x in r)
      out.append((p.max(), (p>2.0001).sum(), (p>3).sum(), pm/1000, sum(float(x['solve_ms']) for x in r)/1000))
    o=np.array(out)
    print(f'{scene:5s} {tag:5s} max pen mm', ' '.join('%.1f'%v for v in o[:,0]), '| steps >2mm', ' '.join('%d'%v for v in o[:,1]), '| >3mm', ' '.join('%d'%v for v in o[:,2]), '| project s %.2f solve s %.1f'%(o[:,3].sum(), o[:,4].sum()))
