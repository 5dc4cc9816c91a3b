#!/bin/bash
# METIS option variants on the partition benchmark (with options_env.patch applied and built).
# Usage: variants.sh (from the repository root)

run() { env "$@" build/rbpart_bench_partition --benchmark_filter='metis\+none/pile:1000/' --benchmark_counters_tabular=true --benchmark_repetitions=3 --benchmark_report_aggregates_only=true 2>&1 | grep median | awk -v v="$*" '{print v, $1, $2, $3, $7, $9}'; }
run X=base
run RB_NITER=1
run RB_NITER=3
run RB_CTYPE=0
run RB_IPTYPE=1
run RB_NO2HOP=1
run RB_NITER=1 RB_CTYPE=0
