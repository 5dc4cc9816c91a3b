#!/bin/bash
# The solver's six scenes, one solver thread, stats into /tmp/scenes/TAG_NAME.csv; sum.py TAG... summarises.
BIN=$1; TAG=$2; mkdir -p /tmp/scenes
run() { name=$1; shift; $BIN simulate --threads 1 "$@" --stats /tmp/scenes/${TAG}_$name.csv -q; }
run rock --scene rock_pile
run bp --scene box_pile --set mass_ratio_set=1
run hard --scene box_pile --set mass_ratio_set=1 --set dt=0.01 --set layers=12 --steps 500
run chain --scene chain_drop
run log --scene log_tower
run large --scene large_rock_pile
