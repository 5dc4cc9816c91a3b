#!/bin/bash
# Whole runs of the path experiment, one solver thread, into /tmp/pr/TAG_SCENE_SEED.csv.
# Usage: VARIANTS="TAG:ENV,ENV... ..." [BINDEF=RBPART] [EXTRA_ARGS="--max-factorizations 100"] runs.sh SCENE "SEEDS"
#   SCENE: rock, bp60 (box pile h = 1/60), bp100 (h = 0.01, 500 steps), lrp (Large Rock Pile).
#   A variant may name its own binary as TAG:ENV@RBPART. sum.py and ../ratio_test_flips/stats.py read /tmp/pr.
OUT=/tmp/pr; SC=$1; SEEDS="$2"; mkdir -p $OUT
for s in $SEEDS; do
  for v in $VARIANTS; do
    BIN=${v#*@}; [ "$BIN" = "$v" ] && BIN=${BINDEF:-/tmp/pr/rbpart}; v=${v%@*}
    tag=${v%%:*}; e=${v#*:}
    case $SC in
      rock) args="--scene rock_pile --set seed=$s";;
      bp60) args="--scene box_pile --set mass_ratio_set=1 --set seed=$s";;
      bp100) args="--scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500 --set seed=$s";;
      lrp) args="--scene large_rock_pile --set seed=$s";;
    esac
    [ -f "$OUT/${tag}_${SC}_$s.csv" ] || env ${e//,/ } timeout 900 $BIN simulate --threads 1 $args $EXTRA_ARGS --stats "$OUT/${tag}_${SC}_$s.csv" -q > /dev/null 2>&1
  done
done
