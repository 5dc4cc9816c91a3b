#!/usr/bin/env bash
# A tiny case of the peers' comparison, for scripts/test.sh: builds bench/peers/ into
# build-peers/peers, checks the run watchdog on stand-in engines, runs every engine and solver for 20
# steps of the 1:1000 stack, and checks that a real run whose steps are fast is never stopped. Needs
# build/rbpart and the packages of scripts/install_peers.sh. About 20 s after the build.
set -euo pipefail
cd "$(dirname "$0")/../.."
cmake -S bench/peers -B build-peers/peers -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-peers/peers -j "$(nproc)" >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The watchdog: a fast run is never stopped, a slow step is stopped at that step, a full stderr
# does not block a run, lines held back are a harness error (run_peers.py, self_test).
/usr/bin/python3 bench/peers/run_peers.py --self-test >"$out/self-test.txt" || { cat "$out/self-test.txt" >&2; exit 1; }
/usr/bin/python3 bench/peers/run_peers.py --scenes stack_1_1000 --steps 20 --out "$out/stack" --work "$out/runs" >/dev/null
# rbpart direct on the 200-box pile: no step of the first 100 takes 0.1 s, but about 24 steps'
# lines fill a 4 KiB pipe block, and such blocks took longer than 0.25 s; a watchdog that got the
# lines a block at a time (the bug of the first sweep) stopped this run.
/usr/bin/python3 bench/peers/run_peers.py --scenes box_pile_200 --engines rbpart:direct --steps 100 --step-budget 0.25 \
  --out "$out/pile" --work "$out/runs" >/dev/null
# Every run must complete its steps and report a residual.
/usr/bin/python3 - "$out/stack/table.csv" "$out/pile/table.csv" <<'PY'
import csv, sys
stack, pile = (list(csv.DictReader(open(path))) for path in sys.argv[1:])
bad = [f"{r['scene']} {r['solver']}: {r['steps']} steps, {r['stopped'] or 'no residual'}"
       for rows, steps in ((stack, "20/20"), (pile, "100/100")) for r in rows
       if r["steps"] != steps or r["stopped"] or r["residual_max"] == ""]
for s in bad:
    print(f"peers smoke: {s}", file=sys.stderr)
print(f"peers smoke: watchdog self-test passed; {len(stack) + len(pile) - len(bad)} runs passed, {len(bad)} failed")
sys.exit(1 if bad or len(stack) != 8 or len(pile) != 1 else 0)
PY
