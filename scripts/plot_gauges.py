#!/usr/bin/python3
"""Plots a run's wave gauges, velocity probes and wall loads against time (PNG; Debian's matplotlib:
run with /usr/bin/python3).

    scripts/plot_gauges.py RUN_DIR [--out DIR]
    scripts/plot_gauges.py --observers FILE [--loads FILE] [--still-water LEVEL] [--out DIR]

RUN_DIR holds observers.csv and, where the case has wall bodies, loads.csv (either may be given
on its own instead). Writes to DIR (default: RUN_DIR, else the observer file's folder):
    gauges.png      one panel per gauge: the elevation (or, with --still-water, the elevation
                    minus that level: the free surface's displacement)
    velocities.png  one panel per velocity probe, its components (only if the file has probes)
    loads.png       one row per wall body: its force components, and its moment beside them

What the files are assumed to hold (the columns issue 22 names; a column not matching is ignored):
  observer CSV (observers.csv): lines starting with '#' are comments; the first other line is the
    header; a column `time`; each wave gauge a column `gauge_<name>` (the elevation, a level
    along -gravity, in length units; a dry gauge reads its line's bottom, a submerged one its
    top: sph/wave_gauge.hpp); each velocity probe the columns `velocity_<name>_x`,
    `velocity_<name>_y` (and `velocity_<name>_z` in 3D).
  loads CSV (loads.csv): the same comment and header rules; a column `time`, then per wall body
    `<body>_fx`, `<body>_fy` (and `<body>_fz` in 3D), the force on the body, and its moment about
    the case's point: `<body>_mz` (or `<body>_m`) in 2D, `<body>_mx`, `<body>_my`, `<body>_mz` in
    3D. Body names may hold '_': a column is split at its last '_'.
Numbers as Python's float() reads them ("nan" and "inf" too). Errors are one line naming the file.
"""
import argparse
import os
import re
import sys

import matplotlib

from observer_csv import read_columns

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fail(message):
    sys.stderr.write("plot_gauges.py: " + message + "\n")
    sys.exit(1)


def plot_gauges(header, columns, still_water, out):
    gauges = [name for name in header if name.startswith("gauge_")]
    if not gauges:
        return None
    time = columns["time"]
    fig, axes = plt.subplots(len(gauges), 1, sharex=True, figsize=(8, 1.8 + 1.6 * len(gauges)), squeeze=False)
    for ax, name in zip(axes[:, 0], gauges):
        values = columns[name]
        if still_water is not None:
            values = [v - still_water for v in values]
        ax.plot(time, values, lw=1.0)
        ax.set_ylabel("η" if still_water is not None else "elevation")
        ax.set_title(name[len("gauge_"):], fontsize=9, loc="left")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time")
    what = "free-surface displacement (elevation − %g)" % still_water if still_water is not None else "elevation"
    fig.suptitle("Wave gauges: " + what)
    fig.tight_layout()
    path = os.path.join(out, "gauges.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_velocities(header, columns, out):
    probes = {}
    for name in header:
        m = re.fullmatch(r"velocity_(.+)_([xyz])", name)
        if m:
            probes.setdefault(m.group(1), []).append((m.group(2), name))
    if not probes:
        return None
    time = columns["time"]
    fig, axes = plt.subplots(len(probes), 1, sharex=True, figsize=(8, 1.8 + 1.6 * len(probes)), squeeze=False)
    for ax, (probe, components) in zip(axes[:, 0], probes.items()):
        for axis, name in components:
            ax.plot(time, columns[name], lw=1.0, label="v_" + axis)
        ax.set_title(probe, fontsize=9, loc="left")
        ax.set_ylabel("velocity")
        ax.legend(fontsize=8, loc="upper right")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time")
    fig.suptitle("Velocity probes")
    fig.tight_layout()
    path = os.path.join(out, "velocities.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


LOAD_COLUMN = re.compile(r"(.+)_(fx|fy|fz|mx|my|mz|m)")


def plot_loads(header, columns, out):
    bodies = {}
    for name in header:
        m = LOAD_COLUMN.fullmatch(name)
        if m:
            kind = "force" if m.group(2).startswith("f") else "moment"
            bodies.setdefault(m.group(1), {"force": [], "moment": []})[kind].append((m.group(2), name))
    if not bodies:
        return None
    time = columns["time"]
    fig, axes = plt.subplots(len(bodies), 2, sharex=True, figsize=(11, 1.8 + 2.0 * len(bodies)), squeeze=False)
    for row, (body, kinds) in enumerate(bodies.items()):
        for col, kind in enumerate(("force", "moment")):
            ax = axes[row, col]
            for component, name in kinds[kind]:
                ax.plot(time, columns[name], lw=1.0, label=component)
            ax.set_title(f"{body}: {kind}", fontsize=9, loc="left")
            if kinds[kind]:
                ax.legend(fontsize=8, loc="upper right")
            ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time")
    axes[-1, 1].set_xlabel("time")
    fig.suptitle("Loads on wall bodies")
    fig.tight_layout()
    path = os.path.join(out, "loads.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description="Plot wave gauges, velocity probes and loads against time.")
    parser.add_argument("run_dir", nargs="?", help="a run's output folder (observers.csv, loads.csv)")
    parser.add_argument("--observers", help="the observer CSV (default RUN_DIR/observers.csv)")
    parser.add_argument("--loads", help="the loads CSV (default RUN_DIR/loads.csv where it exists)")
    parser.add_argument("--still-water", type=float, help="plot the gauges' elevation minus this level")
    parser.add_argument("--out", help="the folder for the PNGs (default RUN_DIR or the observer file's)")
    args = parser.parse_args()
    observers, loads = args.observers, args.loads
    if args.run_dir:
        if observers is None and os.path.exists(os.path.join(args.run_dir, "observers.csv")):
            observers = os.path.join(args.run_dir, "observers.csv")
        if loads is None and os.path.exists(os.path.join(args.run_dir, "loads.csv")):
            loads = os.path.join(args.run_dir, "loads.csv")
    if observers is None and loads is None:
        fail("nothing to plot: give a run folder holding observers.csv or loads.csv, or --observers / --loads")
    out = args.out or args.run_dir or os.path.dirname(os.path.abspath(observers or loads))
    os.makedirs(out, exist_ok=True)
    written = []
    if observers:
        header, columns = read_columns(observers, fail)
        written += [plot_gauges(header, columns, args.still_water, out), plot_velocities(header, columns, out)]
        if not any(name.startswith("gauge_") for name in header):
            sys.stderr.write(f"plot_gauges.py: {observers}: no gauge_<name> column\n")
    if loads:
        header, columns = read_columns(loads, fail)
        path = plot_loads(header, columns, out)
        if path is None:
            sys.stderr.write(f"plot_gauges.py: {loads}: no <body>_fx/_fy/_fz/_m.. column\n")
        written.append(path)
    for path in written:
        if path:
            print(path)


if __name__ == "__main__":
    main()
