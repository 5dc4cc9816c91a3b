#!/usr/bin/python3
"""Runs the same scene files through rbpart's solvers and its peers (ODE, Bullet, MuJoCo), one run
after another, each under a step budget and a run budget, and writes into --out one table (markdown
and CSV), the peers' settings as they report them for each run, two figures and the machine's
description. The scene files, final states, per-step CSVs and stderr of the runs go to --work,
outside the results. bench/peers/README.md explains what is measured and how.

  bench/peers/run_peers.py --out bench/results/amd-epyc-2core/peers
  bench/peers/run_peers.py --self-test      # the watchdog on stand-in engines (bench/peers/smoke.sh)
"""
import argparse
import csv
import json
import os
import platform
import pty
import selectors
import signal
import statistics
import subprocess
import sys
import time
import tty
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
REST_SPEED = 0.05  # m/s: at rest when no surface point moves faster at the last step
SETTLED = 1e-9     # docs/design.md: a step is settled when its residual is at most this

# name -> (rbpart scene, --set arguments). Piles: boxes of 0.2-0.5 m, masses from {10, 100, 1000}
# kg, h = 0.01 s, layers chosen so that the highest box starts at 6-10 m.
PILE_LAYERS = {50: 6, 100: 8, 200: 8, 400: 10, 800: 10}
SCENES = {f"box_pile_{n}": ("box_pile", [f"boxes={n}", "mass_ratio_set=1", "dt=0.01", f"layers={layers}"])
          for n, layers in PILE_LAYERS.items()}
SCENES["stack_1_1000"] = ("box_stack", ["boxes=10", "mass_even=1", "mass_odd=1000", "dt=0.01"])
SCENES["chain_100x"] = ("chain_drop", ["end_ratio=100", "dt=0.01"])

# (engine, solver, label). rbpart runs through its CLI, the peers through rbpart_peers.
RUNS = [("rbpart", "direct", "rbpart direct"), ("rbpart", "pgs", "rbpart PGS"),
        ("ode", "dantzig", "ODE dWorldStep (Dantzig)"), ("ode", "quickstep", "ODE dWorldQuickStep (PGS)"),
        ("bullet", "si", "Bullet sequential impulse"), ("bullet", "mlcp", "Bullet MLCP (Dantzig)"),
        ("mujoco", "newton", "MuJoCo Newton"), ("mujoco", "pgs", "MuJoCo PGS")]


def cpu_seconds(pid):
    """User + system CPU time of a process (and its waited-for children), from /proc."""
    try:
        fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return sum(int(x) for x in fields[11:15]) / os.sysconf("SC_CLK_TCK")


def watch(cmd, step_budget, run_budget, setup_budget):
    """Runs cmd, reading one CSV line per finished step from its standard output, and stops it
    (SIGTERM, then SIGKILL 10 s later) when
      - the step under way has used more than step_budget s of CPU since the previous line,
      - the steps together have used more than run_budget s of CPU (setup not counted),
      - the step under way has not finished after 10 x step_budget s of wall time,
      - setup (until the CSV header) takes longer than setup_budget s of wall time.
    CPU time, not wall time: on a shared machine a niced run waits for others' work.

    The program's standard output is a pseudo-terminal, not a pipe: stdio streams (rbpart writes
    its --stats - through a FILE* of its own on a duplicate of descriptor 1, which stdbuf does not
    reach) are line-buffered on a terminal and fully buffered on a pipe, where a step's line would
    come only with the next 4 KiB block, about 24 steps later, and the CPU of those steps would be
    charged to one. Standard error is read as it comes, so a chatty engine never blocks on a full
    pipe. After a stop the output is read to its end (rbpart finishes the step under way on
    SIGTERM and prints its line); more than one line after a stop means that lines did not come as
    steps ended, and the stop is reported as a harness error, not as the engine's.
    Returns (rows, stop reason or '', stderr)."""
    master, slave = pty.openpty()
    tty.setraw(slave)  # no newline translation, no echo
    try:
        proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=slave, stderr=subprocess.PIPE)
    finally:
        os.close(slave)  # the child holds the only other end: its exit ends the output

    def end(*_):  # stopping this script stops its run too
        proc.kill()
        sys.exit(128 + signal.SIGTERM)
    previous_handler = signal.signal(signal.SIGTERM, end)
    sel = selectors.DefaultSelector()
    sel.register(master, selectors.EVENT_READ, "out")
    sel.register(proc.stderr.fileno(), selectors.EVENT_READ, "err")
    header, rows, pending, err = None, [], b"", bytearray()
    reason, stopped_at, rows_at_stop = "", None, 0
    started = last_wall = time.monotonic()
    cpu_start = cpu_last = 0.0
    while sel.get_map():
        for key, _ in sel.select(timeout=0.2):
            try:
                chunk = os.read(key.fd, 1 << 16)
            except OSError:  # EIO: the terminal's other end is closed
                chunk = b""
            if not chunk:
                sel.unregister(key.fd)
            elif key.data == "err":
                err += chunk
            else:
                *complete, pending = (pending + chunk).split(b"\n")
                if complete:
                    last_wall, cpu_last = time.monotonic(), cpu_seconds(proc.pid)
                for line in complete:
                    fields = line.decode(errors="replace").strip().split(",")
                    if header is None:
                        header, cpu_start = fields, cpu_last
                    elif len(fields) == len(header):
                        rows.append(dict(zip(header, fields)))
        if stopped_at is not None:
            if proc.poll() is None and time.monotonic() - stopped_at > 10:
                proc.kill()
            continue
        if proc.poll() is not None:
            continue
        now, step = time.monotonic(), len(rows) + 1
        if header is None:
            if now - started > setup_budget:
                reason = f"setup took longer than {setup_budget:g} s"
        else:
            cpu = cpu_seconds(proc.pid)
            if cpu - cpu_start > run_budget:
                reason = f"run budget {run_budget:g} s of CPU reached after {len(rows)} steps"
            elif cpu - cpu_last > step_budget:
                reason = f"step {step} used more than {step_budget:g} s of CPU"
            elif now - last_wall > 10 * step_budget:
                reason = f"step {step} not done after {10 * step_budget:g} s of wall time"
        if reason:
            proc.send_signal(signal.SIGTERM)
            stopped_at, rows_at_stop = time.monotonic(), len(rows)
    proc.wait()
    os.close(master)
    proc.stderr.close()
    signal.signal(signal.SIGTERM, previous_handler)
    err = err.decode(errors="replace")
    if stopped_at is not None and len(rows) - rows_at_stop > 1:
        reason = (f"harness error: {len(rows) - rows_at_stop} steps' lines came after the stop "
                  f"({reason}); the lines did not come as the steps ended")
    elif not reason and proc.returncode != 0:
        reason = "error: " + (err.strip().splitlines() or [f"exit {proc.returncode}"])[-1]
    return rows, reason, err


# A stand-in engine for --self-test: prints the peers' CSV through a stream of its own on a
# duplicate of descriptor 1, as rbpart does (Python's, like C's, is line-buffered on a terminal
# only), burning CPU per step. argv: steps, slow step, its CPU s, other steps' CPU s, bytes to write
# to stderr first, "buffered" (always fully buffered; flushes on SIGTERM, as rbpart keeps its steps).
STAND_IN = r"""
import os, signal, sys, time
steps, slow, slow_s, step_s, noise = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
sys.stderr.write("x" * noise)
sys.stderr.flush()
out = open(os.dup(1), "w", buffering=1 << 16) if sys.argv[6] == "buffered" else os.fdopen(os.dup(1), "w")
signal.signal(signal.SIGTERM, lambda *_: (out.flush(), os._exit(143)))
out.write("step,contacts,total_ms,solve_ms,blcp_residual,max_penetration,pad\n")
out.flush()
for k in range(1, steps + 1):
    t = time.process_time()
    while time.process_time() - t < (slow_s if k == slow else step_s):
        pass
    out.write(f"{k},0,{1000 * (time.process_time() - t):.3f},0,-1,0,{'.' * 150}\n")
"""


def self_test():
    """The watchdog on stand-in engines: each case must end as expected. Returns the failures."""
    cases = [  # (what, stand-in arguments, step budget, run budget, expected steps, expected reason's start)
        ("fast steps, each far below the step budget, 24 lines a 4 KiB block: never stopped",
         (60, 0, 0, 0.02, 0, "stdio"), 0.2, 30, 60, ""),
        ("one slow step: stopped at that step", (6, 4, 1.5, 0.01, 0, "stdio"), 0.3, 30, 3, "step 4 "),
        ("1 MiB on stderr before the steps: never stopped", (5, 0, 0, 0.01, 1 << 20, "stdio"), 0.2, 30, 5, ""),
        ("the run budget", (40, 0, 0, 0.05, 0, "stdio"), 1, 0.5, None, "run budget 0.5 s"),
        ("lines held back by the engine: a harness error, not a slow step",
         (60, 0, 0, 0.02, 0, "buffered"), 0.2, 30, None, "harness error"),
    ]
    failures = []
    for what, args, step_budget, run_budget, steps, start in cases:
        cmd = [sys.executable, "-c", STAND_IN] + [str(a) for a in args]
        t0 = time.monotonic()
        rows, reason, _ = watch(cmd, step_budget, run_budget, setup_budget=60)
        ok = reason.startswith(start) if start else reason == ""
        ok = ok and (steps is None or len(rows) == steps)
        print(f"self-test {'ok  ' if ok else 'FAIL'} {what}: {len(rows)} steps, "
              f"{reason or 'not stopped'} ({time.monotonic() - t0:.1f} s)", flush=True)
        if not ok:
            failures.append(what)
    print(f"self-test: {len(cases) - len(failures)} passed, {len(failures)} failed")
    return failures


def nice(cmd):
    return ["nice", "-n", "10"] + cmd


def rel(path):
    """A path as the commands in the results give it: relative to the repository when inside it."""
    path = os.path.abspath(path)
    return os.path.relpath(path, ROOT) if path.startswith(str(ROOT) + os.sep) else path


def export_scenes(rbpart, names, folder):
    """Writes each scene file; returns {name: path} and {name: the command that writes it}."""
    paths, commands = {}, {}
    for name in names:
        scene, sets = SCENES[name]
        args = [str(rbpart), "scenes", "--export", scene] + [a for s in sets for a in ("--set", s)]
        path = folder / f"{name}.json"
        path.write_text(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
        paths[name] = path
        commands[name] = " ".join([rel(args[0])] + args[1:] + [">", rel(path)])
    return paths, commands


def summarise(rows, steps_asked):
    def col(key):
        return [float(r[key]) for r in rows if key in r and r[key] not in ("", "nan")]
    out = {"steps": f"{len(rows)}/{steps_asked}"}
    for key, name in (("total_ms", "step_ms"), ("solve_ms", "solve_ms")):
        values = col(key)
        out[f"{name}_median"] = statistics.median(values) if values else None
        out[f"{name}_max"] = max(values) if values else None
    pen = col("max_penetration")
    out["max_penetration_mm"] = 1000 * max(pen) if pen else None
    res = [r for r, c in zip(col("blcp_residual"), col("contacts")) if r >= 0 and c > 0]
    out["residual_median"] = statistics.median(res) if res else None
    out["residual_max"] = max(res) if res else None
    out["unsettled_steps"] = sum(r > SETTLED for r in res) if res else None
    return out


def fmt(value, kind):
    if value is None:
        return "—"
    if kind == "ms":
        return f"{value:.3g}" if value < 100 else f"{value:.0f}"
    if kind == "mm":
        return f"{value:.2f}"
    if kind == "J":
        return f"{value:.3g}"
    if kind == "res":
        return f"{value:.1e}"
    return str(value)


COLUMNS = [("scene", "scene", None), ("bodies", "bodies", None), ("engine", "engine / solver", None),
           ("steps", "steps run", None), ("step_ms_median", "ms/step median", "ms"), ("step_ms_max", "ms/step max", "ms"),
           ("solve_ms_median", "solve ms median", "ms"), ("solve_ms_max", "solve ms max", "ms"),
           ("max_penetration_mm", "max pen. mm (own)", "mm"), ("end_penetration_mm", "end pen. mm (common)", "mm"),
           ("end_kinetic_energy", "end KE J", "J"), ("at_rest", "at rest", None),
           ("residual_median", "residual median", "res"), ("residual_max", "residual max", "res"),
           ("unsettled_steps", "steps > 1e-9", None), ("stopped", "stopped", None)]


def write_table(results, out):
    with open(out / "table.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=[c[0] for c in COLUMNS] + ["solver", "command"], extrasaction="ignore")
        w.writeheader()
        for r in results:
            w.writerow(r)
    lines = ["| " + " | ".join(c[1] for c in COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for r in results:
        cells = [fmt(r.get(k), kind) if kind else ("—" if r.get(k) is None else str(r[k])) for k, _, kind in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    (out / "table.md").write_text("\n".join(lines) + "\n")


def plot(results, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    piles = [r for r in results if r["scene"].startswith("box_pile_")]
    for key, ylabel, name in (("step_ms_median", "ms per step (median over the run)", "ms_per_step"),
                              ("max_penetration_mm", "max penetration over the run (mm, engine's own)", "penetration")):
        fig, ax = plt.subplots(figsize=(8, 5))
        for label in dict.fromkeys(r["engine"] for r in piles):
            pts = [(r["bodies"], r[key]) for r in piles if r["engine"] == label and r.get(key) is not None
                   and not r["stopped"]]
            if pts:
                ax.plot(*zip(*sorted(pts)), marker="o", label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("boxes")
        ax.set_ylabel(ylabel)
        ax.set_title("box piles, masses {10, 100, 1000} kg, h = 0.01 s (complete runs only)")
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_lines():
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / f"{name}.png", dpi=110)
        plt.close(fig)


def versions():
    names = ["libode8", "libode-dev", "libbullet3.24", "libbullet-dev", "libbullet-extras-dev", "libmujoco2.2.2",
             "libmujoco-dev", "g++-12", "python3-matplotlib"]
    out = subprocess.run(["dpkg-query", "-W", "-f=${Package} ${Version}\\n"] + names, capture_output=True, text=True).stdout
    return dict(line.split(" ", 1) for line in out.splitlines())


def machine(args, started, scene_commands):
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "")
    git = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = bool(subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                                capture_output=True, text=True).stdout.strip())
    load = os.getloadavg()
    return {"command": " ".join([sys.argv[0]] + sys.argv[1:]), "started": started,
            "written": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "cpu": cpu,
            "logical_cpus": os.cpu_count(), "os": platform.platform(), "python": platform.python_version(),
            "git_revision": git, "git_dirty": dirty, "nice": 10, "rbpart_threads": 1,
            "load_average_at_end": [round(x, 2) for x in load],
            "shared_machine": args.shared, "step_budget_s": args.step_budget, "run_budget_s": args.run_budget,
            "rest_speed_m_per_s": REST_SPEED, "packages": versions(), "scene_files": scene_commands,
            "work_folder": rel(args.work)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rbpart", default=str(ROOT / "build" / "rbpart"))
    p.add_argument("--peers", default=str(ROOT / "build-peers" / "peers" / "rbpart_peers"))
    p.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--engines", nargs="+", default=[f"{e}:{s}" for e, s, _ in RUNS],
                   help="engine:solver pairs, e.g. rbpart:direct ode:quickstep")
    p.add_argument("--steps", type=int, help="steps per run (default: the scene's)")
    p.add_argument("--step-budget", type=float, default=2.0, help="seconds of CPU; a longer step stops that run")
    p.add_argument("--run-budget", type=float, default=30.0, help="seconds of CPU for a run's steps")
    p.add_argument("--mujoco-memory-gib", type=float, default=1.9,
                   help="what MuJoCo 2.2 may allocate for its constraint arrays (at most 1.9)")
    p.add_argument("--shared", action="store_true", help="record that the machine was shared with other work")
    p.add_argument("--out", help="the results: table, settings, figures, machine.json")
    p.add_argument("--work", default=str(ROOT / "build-peers" / "runs"),
                   help="the runs' scene files, final states, per-step CSVs and stderr (default: build-peers/runs)")
    p.add_argument("--self-test", action="store_true", help="check the watchdog on stand-in engines and exit")
    args = p.parse_args()
    if args.self_test:
        sys.exit(1 if self_test() else 0)
    if not args.out:
        p.error("--out is required")
    started = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    out, work = Path(args.out), Path(args.work)
    out.mkdir(parents=True, exist_ok=True)
    for sub in ("scenes", "steps", "settings", "states", "stderr"):
        (work / sub).mkdir(parents=True, exist_ok=True)
    built = subprocess.run([args.peers, "engines"], capture_output=True, text=True).stdout.split() \
        if Path(args.peers).exists() else []
    scenes, scene_commands = export_scenes(args.rbpart, args.scenes, work / "scenes")
    results, settings = [], {}
    for name, path in scenes.items():
        scene = json.loads(path.read_text())
        bodies = sum(not b.get("static", False) for b in scene["bodies"])
        steps = args.steps or scene["steps"]
        for engine, solver, label in RUNS:
            if f"{engine}:{solver}" not in args.engines:
                continue
            tag = f"{name}.{engine}_{solver}"
            state, settings_file = work / "states" / f"{tag}.json", work / "settings" / f"{tag}.json"
            for stale in (state, settings_file, work / "steps" / f"{tag}.csv", work / "stderr" / f"{tag}.txt"):
                stale.unlink(missing_ok=True)
            if engine == "rbpart":
                cmd = [args.rbpart, "simulate", "--scene", str(path), "--solver", solver, "--threads", "1",
                       "--steps", str(steps), "--stats", "-", "--state", str(state), "--quiet"]
            else:
                cmd = [args.peers, "run", "--engine", engine, "--solver", solver, "--scene", str(path), "--steps", str(steps),
                       "--state", str(state), "--settings", str(settings_file),
                       "--mujoco-memory-gib", str(args.mujoco_memory_gib)]
            result = {"scene": name, "bodies": bodies, "engine": label, "solver": f"{engine}:{solver}",
                      "command": " ".join(["nice", "-n", "10"] + [rel(c) if os.path.isabs(c) else c for c in cmd])}
            if engine != "rbpart" and engine not in built:
                result.update(steps=f"0/{steps}", stopped="not built here")
                results.append(result)
                continue
            print(f"{name:>14}  {label:<28}", end=" ", flush=True)
            t0 = time.monotonic()
            rows, reason, err = watch(nice(cmd), args.step_budget, args.run_budget, setup_budget=60)
            result.update(summarise(rows, steps), stopped=reason)
            if rows:
                with open(work / "steps" / f"{tag}.csv", "w", newline="") as f:
                    w = csv.DictWriter(f, fieldnames=list(rows[0]))
                    w.writeheader()
                    w.writerows(rows)
            if err:
                (work / "stderr" / f"{tag}.txt").write_text(err)
            if settings_file.exists():
                try:
                    settings[tag] = json.loads(settings_file.read_text())
                except ValueError:
                    settings[tag] = {"not_json": settings_file.read_text()}
            if not reason and state.exists():
                m = json.loads(subprocess.run([args.peers, "measure", "--scene", str(path), "--state", str(state)],
                                              check=True, capture_output=True, text=True).stdout)
                result.update(end_kinetic_energy=m["kinetic_energy"], end_penetration_mm=1000 * m["penetration"],
                              at_rest="yes" if m["max_point_speed"] < REST_SPEED else f"no ({m['max_point_speed']:.2f} m/s)")
            print(f"{time.monotonic() - t0:6.1f} s  {result['steps']}  {reason}", flush=True)
            results.append(result)
            write_table(results, out)  # as it goes: a sweep cut short keeps its finished runs
            (out / "settings.json").write_text(json.dumps(settings, indent=1) + "\n")
    write_table(results, out)
    plot(results, out)
    (out / "machine.json").write_text(json.dumps(machine(args, started, scene_commands), indent=2) + "\n")


if __name__ == "__main__":
    main()
