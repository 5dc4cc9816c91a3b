#!/bin/bash
# run.sh SCENE_ARGS_TAG SEEDS ; VARIANTS="tag:ENV ..."
BIN=${BIN:-/tmp/pr/rbpart}; OUT=/tmp/pr; SC=$1; SEEDS="$2"
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
