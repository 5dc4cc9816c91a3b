#!/bin/bash
# Usage: DIR=... STATE=... compare.sh  (DIR holds rbpart_base and rbpart_schur, the two builds;
# STATE: a resting Large Rock Pile, build/rbpart simulate --scene large_rock_pile --steps 300 --state STATE)
# Prints config|build|repeat|mean solve ms of steps 2-10|mean critical path ms.
# alternate binaries; 10 resting LRP steps at 2 threads
for rep in 1 2 3; do
for cfg in "direct" "metis 32" "metis 128" "metis 300" "mix 32"; do
for b in base schur; do
  set -- $cfg
  if [ "$1" = direct ]; then args="--solver direct"; else args="--solver substructured --partitioner $1 --nmax $2"; [ "$1" = mix ] && args="$args --refine fm"; fi
  $DIR/rbpart_$b simulate --scene large_rock_pile --initial-state $STATE --steps 10 --threads 2 $args -q --stats $DIR/cmp.csv
  awk -F, -v B=$b -v C="$cfg" -v R=$rep 'NR>2{s+=$15;c+=$26;n++} END{printf "%s|%s|%d|%.2f|%.2f\n", C, B, R, s/n, c/n}' $DIR/cmp.csv
done; done; done
