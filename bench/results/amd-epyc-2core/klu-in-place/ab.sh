#!/bin/bash
# ab2.sh REPS THREADS BIN... -- ARGS : alternate runs; print min and median of total solve_ms per binary
R=$1; T=$2; shift 2; BINS=(); while [ "$1" != "--" ]; do BINS+=("$1"); shift; done; shift
for ((i=0;i<R;i++)); do for b in "${BINS[@]}"; do
  $b simulate --scene large_rock_pile --initial-state /tmp/s25/lrp300.json --threads $T "$@" --stats /tmp/s26/ab2.csv -q
  awk -F, -v b=$b 'NR>1{s+=$15} END{printf "%s %.1f\n", b, s}' /tmp/s26/ab2.csv
done; done | /usr/bin/python3 -c "
import sys,statistics as st,collections
d=collections.defaultdict(list)
for l in sys.stdin: b,v=l.split(); d[b].append(float(v))
for b,v in d.items(): print(f'{b:24s} min {min(v):7.1f} median {st.median(v):7.1f} n {len(v)}')
"
