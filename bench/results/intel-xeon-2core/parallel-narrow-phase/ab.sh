#!/bin/bash
# Five alternating runs of 20 steps from a resting Large Rock Pile (the state at step 300), the
# build before (BASE) and this one (NEW), at 1 and 2 threads: per run the mean collide stage and
# the mean whole step (ms), skipping the first two steps (the resumed run's first step is cold).
# Usage: ab.sh BASE/rbpart NEW/rbpart   (the state: rbpart simulate --scene large_rock_pile
#        --threads 2 --steps 300 --state /tmp/lrp300.json)
for r in 1 2 3 4 5; do for t in 1 2; do for b in "$1" "$2"; do
  $b simulate --scene large_rock_pile --initial-state /tmp/lrp300.json --steps 20 --threads $t --stats /tmp/ab.csv -q
  python3 -c "
import csv; r=list(csv.DictReader(open('/tmp/ab.csv')))[2:]
print('$b', $t, round(sum(float(x['collide_ms']) for x in r)/len(r),2), round(sum(float(x['total_ms']) for x in r)/len(r),2))"
done; done; done
