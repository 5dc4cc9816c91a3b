#!/usr/bin/env python3
"""Figures 3-5 of the partitioning study, drawn from the tables `rbpart bench` writes.

usage: /usr/bin/python3 scripts/plot_study.py DIR

Reads DIR/table1.csv, DIR/scaling.csv, DIR/steps.csv and DIR/machine.json; writes DIR/fig3, fig4,
fig5 and estimates as .png and .svg (each written to a temporary name and renamed, so a figure is whole or absent).
fig3: mean solve time of every combination, per scene (grouped bars).
fig4: Rock Pile solve time against rock count, one line per combination.
fig5: Log Tower solve time per step, MinDP with none, KL and FM.
estimates: per Table 1 scene and configuration, the measured solve time at every thread count the
study ran beside the estimates on 8 and 16 cores, max(critical path, work / cores), with their
min-max over the recorded steps.
Where a study varies n_max or threads, the figures show the first value of each (docs/study.md);
the estimates figure shows every thread count measured, and the estimates of the fewest threads.
Needs matplotlib (Debian: python3-matplotlib, with the system /usr/bin/python3).
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

PARTITIONERS = ["bfs", "mindp", "maxdp", "mr", "mix", "metis"]
REFINERS = ["none", "kl", "fm", "fm-rollback"]
NAMES = {"bfs": "BFS", "mindp": "MinDP", "maxdp": "MaxDP", "mr": "MR", "mix": "MIX", "metis": "METIS",
         "none": "no refinement", "kl": "KL", "fm": "FM", "fm-rollback": "FM (rollback)"}
REFINER_COLOURS = {"none": "#4c72b0", "kl": "#dd8452", "fm": "#55a868", "fm-rollback": "#8172b3"}
PARTITIONER_COLOURS = {"bfs": "#4c72b0", "mindp": "#dd8452", "maxdp": "#55a868", "mr": "#c44e52",
                       "mix": "#8172b3", "metis": "#7f7f7f"}
REFINER_STYLES = {"none": "-", "kl": "--", "fm": ":", "fm-rollback": "-."}
DIRECT = dict(color="black", linewidth=1.4, label="direct (monolithic)")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def combination(row):
    name = NAMES[row["partitioner"]]
    return name if row["refine"] == "none" else name + "+" + NAMES[row["refine"]]


def order(values, reference):
    """The values present, in the reference order, unknown ones last."""
    present = list(dict.fromkeys(values))
    return [v for v in reference if v in present] + [v for v in present if v not in reference]


def selection(rows):
    """n_max and threads shown: those of the first substructured row."""
    for r in rows:
        if r["solver"] == "substructured":
            return r["nmax"], r["threads"]
    return None, None


def shown(rows, nmax, threads):
    """Substructured rows of the selection, and direct rows of the same thread count."""
    return [r for r in rows if r["threads"] == threads and (r["solver"] == "direct" or r["nmax"] == nmax)]


def subtitle(machine, nmax, threads):
    revision = machine.get("git_revision", "unknown")[:10] + (" (modified)" if machine.get("git_dirty") else "")
    return "{} · {} solver thread{} · n_max {} · preset {} · rbpart {}".format(
        machine.get("cpu", "unknown CPU"), threads, "" if threads == "1" else "s", nmax, machine.get("preset", "?"),
        revision)


def save(fig, directory, name):
    for ext in ("png", "svg"):
        temp = os.path.join(directory, ".{}.tmp.{}".format(name, ext))
        fig.savefig(temp, dpi=150, bbox_inches="tight")
        os.replace(temp, os.path.join(directory, "{}.{}".format(name, ext)))
    plt.close(fig)


def figure3(directory, table, machine):
    nmax, threads = selection(table)
    rows = shown(table, nmax, threads)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    if not scenes or nmax is None:
        return "no Table 1 rows"
    cols = min(2, len(scenes))
    nrows = math.ceil(len(scenes) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(6.5 * cols, 4.2 * nrows), squeeze=False)
    for ax, scene in zip(axes.flat, scenes):
        here = [r for r in rows if r["scene"] == scene]
        sub = [r for r in here if r["solver"] == "substructured"]
        partitioners = order([r["partitioner"] for r in sub], PARTITIONERS)
        refiners = order([r["refine"] for r in sub], REFINERS)
        width = 0.8 / len(refiners)
        for k, refiner in enumerate(refiners):
            xs, ys = [], []
            for i, p in enumerate(partitioners):
                for r in sub:
                    if r["partitioner"] == p and r["refine"] == refiner:
                        xs.append(i - 0.4 + (k + 0.5) * width)
                        ys.append(float(r["mean_solve_ms"]))
            ax.bar(xs, ys, width * 0.95, color=REFINER_COLOURS.get(refiner, "#999999"), label=NAMES[refiner])
        for r in here:
            if r["solver"] == "direct":
                ax.axhline(float(r["mean_solve_ms"]), linestyle="--", **DIRECT)
        ax.set_xticks(range(len(partitioners)))
        ax.set_xticklabels([NAMES[p] for p in partitioners])
        ax.set_ylabel("mean solve time per step (ms)")
        ax.set_title("{} ({} bodies)".format(scene, here[0]["dynamic_bodies"]))
        ax.grid(axis="y", alpha=0.3)
        ax.set_axisbelow(True)
    for ax in list(axes.flat)[len(scenes):]:
        ax.set_visible(False)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, -0.02), frameon=False)
    fig.suptitle("Figure 3: substructured solve time per partitioner and refinement\n" +
                 subtitle(machine, nmax, threads), fontsize=11)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    save(fig, directory, "fig3")
    return None


def figure4(directory, scaling, machine):
    nmax, threads = selection(scaling)
    rows = shown(scaling, nmax, threads)
    if not rows or nmax is None:
        return "no scaling rows"
    fig, ax = plt.subplots(figsize=(9, 5.5))
    sub = [r for r in rows if r["solver"] == "substructured"]
    for p in order([r["partitioner"] for r in sub], PARTITIONERS):
        for refiner in order([r["refine"] for r in sub if r["partitioner"] == p], REFINERS):
            line = sorted((int(r["rocks"]), float(r["mean_solve_ms"])) for r in sub
                          if r["partitioner"] == p and r["refine"] == refiner)
            ax.plot([x for x, _ in line], [y for _, y in line], REFINER_STYLES.get(refiner, "-"), marker="o",
                    markersize=3.5, color=PARTITIONER_COLOURS.get(p, "#999999"),
                    label=combination({"partitioner": p, "refine": refiner}))
    direct = sorted((int(r["rocks"]), float(r["mean_solve_ms"])) for r in rows if r["solver"] == "direct")
    ax.plot([x for x, _ in direct], [y for _, y in direct], "-", marker="s", markersize=4, **DIRECT)
    rocks = sorted({int(r["rocks"]) for r in rows})
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(rocks)
    ax.set_xticklabels([str(x) for x in rocks])
    ax.minorticks_off()
    ax.set_xlabel("rocks in the pile (dynamic bodies)")
    ax.set_ylabel("mean solve time per step (ms)")
    ax.grid(which="both", alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, frameon=False)
    ax.set_title("Figure 4: Rock Pile solve time against size\n" + subtitle(machine, nmax, threads), fontsize=11)
    fig.tight_layout()
    save(fig, directory, "fig4")
    return None


def figure5(directory, steps, machine):
    scenes = [s for s in dict.fromkeys(r["scene"] for r in steps) if s.split(":")[0] == "log_tower"]
    if not scenes:
        return "no log_tower scene"
    here = [r for r in steps if r["scene"] == scenes[0]]
    nmax, threads = selection(here)
    rows = shown(here, nmax, threads)
    fig, ax = plt.subplots(figsize=(10, 4.8))
    for refiner in order([r["refine"] for r in rows if r["partitioner"] == "mindp"], REFINERS):
        line = [(int(r["step"]), float(r["solve_ms"])) for r in rows
                if r["solver"] == "substructured" and r["partitioner"] == "mindp" and r["refine"] == refiner]
        ax.plot([x for x, _ in line], [y for _, y in line], linewidth=1.1, color=REFINER_COLOURS.get(refiner),
                label="MinDP " + ("(no refinement)" if refiner == "none" else "+ " + NAMES[refiner]))
    direct = [(int(r["step"]), float(r["solve_ms"])) for r in rows if r["solver"] == "direct"]
    ax.plot([x for x, _ in direct], [y for _, y in direct], color="#999999", linewidth=0.9,
            label="direct (monolithic)")
    ax.set_yscale("log")  # a step where the contacts change costs many times a quiet one
    ax.set_xlabel("time step")
    ax.set_ylabel("solve time (ms, median of repeats)")
    ax.grid(alpha=0.3)
    ax.legend(frameon=False)
    ax.set_title("Figure 5: {} solve time per step\n{}".format(scenes[0], subtitle(machine, nmax, threads)),
                 fontsize=11)
    fig.tight_layout()
    save(fig, directory, "fig5")
    return None


ESTIMATE_CORES = (8, 16)  # of steps.csv's est<c>_ms columns
THREAD_COLOURS = ["#4c72b0", "#8fb1e0", "#2a4a7f", "#c6d7ef"]
ESTIMATE_COLOURS = {8: "#dd8452", 16: "#c44e52"}


def spread(values):
    """(mean, min, max) of the values."""
    return sum(values) / len(values), min(values), max(values)


def figure_estimates(directory, table, steps, machine):
    """Measured solve time at each thread count beside the 8- and 16-core estimates, per scene."""
    scenes = list(dict.fromkeys(r["scene"] for r in table))
    nmax, _ = selection(table)
    if not scenes or nmax is None:
        return "no Table 1 rows"
    if not steps or any("est{}_ms".format(c) not in steps[0] for c in ESTIMATE_CORES):
        return "steps.csv has no estimate columns"
    threads = sorted({r["threads"] for r in steps}, key=int)
    fewest = threads[0]
    series = [("measured, {} thread{}".format(t, "" if t == "1" else "s"), "solve_ms", t, "o",
               THREAD_COLOURS[i % len(THREAD_COLOURS)]) for i, t in enumerate(threads)]
    series += [("estimate, {} cores".format(c), "est{}_ms".format(c), fewest, "v", ESTIMATE_COLOURS[c])
               for c in ESTIMATE_CORES]
    fig, axes = plt.subplots(len(scenes), 1, figsize=(13, 3.9 * len(scenes)), squeeze=False)
    for ax, scene in zip(axes.flat, scenes):
        # Steps with rows only: a step with nothing to solve is no measurement of a solver.
        here = [r for r in steps if r["scene"] == scene and int(r["rows"]) > 0 and
                (r["solver"] == "direct" or r["nmax"] == nmax)]
        sub = [r for r in here if r["solver"] == "substructured"]
        configs = [("direct", "none", "none")]
        for p in order([r["partitioner"] for r in sub], PARTITIONERS):
            for refiner in order([r["refine"] for r in sub if r["partitioner"] == p], REFINERS):
                configs.append(("substructured", p, refiner))
        width = 0.8 / len(series)
        for k, (label, column, t, marker, colour) in enumerate(series):
            xs, ys, lo, hi = [], [], [], []
            for i, (solver, p, refiner) in enumerate(configs):
                values = [float(r[column]) for r in here if r["solver"] == solver and r["threads"] == t and
                          (solver == "direct" or (r["partitioner"] == p and r["refine"] == refiner)) and r[column]]
                values = [v for v in values if v > 0]
                if not values:
                    continue
                mean, low, high = spread(values)
                xs.append(i - 0.4 + (k + 0.5) * width)
                ys.append(mean)
                lo.append(mean - low)
                hi.append(high - mean)
            ax.errorbar(xs, ys, yerr=[lo, hi], fmt=marker, color=colour, markersize=5, capsize=2, elinewidth=1,
                        label=label)
        ax.set_yscale("log")
        ax.set_xticks(range(len(configs)))
        ax.set_xticklabels(["direct" if solver == "direct" else combination({"partitioner": p, "refine": refiner})
                            for solver, p, refiner in configs], rotation=30, ha="right", fontsize=8)
        ax.set_xlim(-0.6, len(configs) - 0.4)
        ax.set_ylabel("solve time per step (ms)")
        bodies = [r["dynamic_bodies"] for r in table if r["scene"] == scene]
        ax.set_title("{} ({} bodies)".format(scene, bodies[0] if bodies else "?"), fontsize=10)
        ax.grid(axis="y", which="both", alpha=0.3)
        ax.set_axisbelow(True)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, -0.01), frameon=False)
    fig.suptitle("Measured solve time beside its estimates on 8 and 16 cores, max(critical path, work / cores)\n"
                 "markers: mean over the recorded steps with rows; bars: min to max; estimates from {} thread{}\n"
                 .format(fewest, "" if fewest == "1" else "s") + subtitle(machine, nmax, ", ".join(threads)),
                 fontsize=11)
    height = fig.get_size_inches()[1]
    fig.tight_layout(rect=(0, 0.35 / height, 1, 1 - 0.65 / height))  # room for the legend and the title
    save(fig, directory, "estimates")
    return None


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    directory = argv[1]
    try:
        with open(os.path.join(directory, "machine.json")) as f:
            machine = json.load(f)
        table = read_csv(os.path.join(directory, "table1.csv"))
        scaling = read_csv(os.path.join(directory, "scaling.csv"))
        steps = read_csv(os.path.join(directory, "steps.csv"))
    except (OSError, ValueError) as e:
        print("plot_study: {}".format(e), file=sys.stderr)
        return 2
    figures = (("fig3", lambda: figure3(directory, table, machine)),
               ("fig4", lambda: figure4(directory, scaling, machine)),
               ("fig5", lambda: figure5(directory, steps, machine)),
               ("estimates", lambda: figure_estimates(directory, table, steps, machine)))
    for name, draw in figures:
        skipped = draw()
        if skipped:
            print("plot_study: {} not drawn: {}".format(name, skipped), file=sys.stderr)
            for ext in ("png", "svg"):  # a figure of an earlier study would not match these tables
                stale = os.path.join(directory, "{}.{}".format(name, ext))
                if os.path.exists(stale):
                    os.remove(stale)
        else:
            print("plot_study: wrote {0}/{1}.png and {0}/{1}.svg".format(directory, name))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
