#!/usr/bin/python3
"""Draws the SPH validation comparisons as PNGs (Debian's matplotlib: run with /usr/bin/python3).

    scripts/plot_sph_validation.py OUT_ROOT [IMAGES_DIR]

OUT_ROOT holds the output folders of `unisph run` (observers.csv in each):
    dambreak_2d/, column_collapse_2d/, column_collapse_2d_dx80/ (optional), hydrostatic_2d/,
    dambreak_2d_H80/, dambreak_2d_H160/, dambreak_2d_H320/ (optional: the wall-pressure profile
    and the arrival at the wall probes at several resolutions; runs to t sqrt(g/H) = 6 are enough),
    dambreak_3d/ (optional: the 3D case, drawn beside them in the arrival plot)
Experimental data: tests/data/validation/.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "tests", "data", "validation")
sys.path.insert(0, HERE)
from sph_run_metrics import first_crossing, window_mean  # noqa: E402  (the figures of docs/validation.md)


def read_experiment(name):
    t, y = [], []
    with open(os.path.join(DATA, name)) as f:
        rows = [r for r in f if not r.startswith("#")]
    for row in list(csv.reader(rows))[1:]:
        t.append(float(row[0]))
        y.append(float(row[1]))
    return t, y


def read_observers(folder):
    path = os.path.join(folder, "observers.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = [r for r in f if not r.startswith("#")]
    reader = csv.DictReader(rows)
    columns = {}
    for row in reader:
        for k, v in row.items():
            columns.setdefault(k, []).append(float(v))
    return columns


# Wall probes of dambreak_2d.toml and the experiment at the same height.
WALL_PROBES = [("wall_0.01H", 0.01, "lobovsky_2014_sensor1.csv", "Lobovsky et al. (2014)"),
               ("wall_0.1H", 0.1, "lobovsky_2014_sensor3.csv", "Lobovsky et al. (2014)"),
               ("wall_0.2H", 0.2, "buchner_2002_wall_pressure.csv", "Buchner (2002)"),
               ("wall_0.267H", 0.2667, "lobovsky_2014_sensor4.csv", "Lobovsky et al. (2014)")]


def runs_with_wall_probes(root, runs):
    """(label, observer columns) of each (folder, label) in runs present under root with the wall probes."""
    for folder, label in runs:
        d = read_observers(os.path.join(root, folder))
        if d and "p_star_wall_0.1H" in d:
            yield label, d


def pressure_profile(root, images):
    """Mean wall pressure over t sqrt(g/H) in [3.5, 5] against height, per resolution, beside the sensors."""
    runs = [("dambreak_2d", "H/dx = 40"), ("dambreak_2d_H80", "H/dx = 80"), ("dambreak_2d_H160", "H/dx = 160"),
            ("dambreak_2d_H320", "H/dx = 320")]
    fig, ax = plt.subplots(figsize=(5, 4.5))
    drawn = False
    for label, d in runs_with_wall_probes(root, runs):
        heights = [y for name, y, _, _ in WALL_PROBES]
        means = [window_mean(d["time_star"], d["p_star_" + name], 3.5, 5.0) for name, _, _, _ in WALL_PROBES]
        ax.plot(means, heights, "o-", ms=4, label="unisph, " + label)
        print("%-18s %s" % (label, "  ".join("%s %.3f" % (n, m) for (n, _, _, _), m in zip(WALL_PROBES, means))))
        drawn = True
    if not drawn:
        plt.close(fig)
        return
    for name, y, data, who in WALL_PROBES:
        t, p = read_experiment(data)
        m = window_mean(t, p, 3.5, 5.0)
        ax.plot(m, y, "ks" if who.startswith("Buchner") else "k^", ms=7, mfc="none",
                label=who if name in ("wall_0.01H", "wall_0.2H") else None)
        print("%-18s %s %.3f" % (who, name, m))
    ax.set_xlabel("mean p / (rho g H) over t sqrt(g/H) in [3.5, 5]")
    ax.set_ylabel("height on the downstream wall / H")
    ax.set_xlim(left=0)
    ax.set_ylim(0, 0.3)
    ax.set_title("2D dam break: wall pressure after the impact")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(images, "sph_dambreak_pressure_profile.png"), dpi=120)


def arrival_at_probes(root, images):
    """First time p/(rho g H) > 0.2 at each wall probe against its height, beside the sensors' own."""
    runs = [("dambreak_2d", "2D, H/dx = 40"), ("dambreak_2d_H80", "2D, H/dx = 80"),
            ("dambreak_2d_H160", "2D, H/dx = 160"), ("dambreak_2d_H320", "2D, H/dx = 320"),
            ("dambreak_3d", "3D (Lobovsky's tank)")]
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    drawn = False
    for label, d in runs_with_wall_probes(root, runs):
        times = [first_crossing(d["time_star"], d["p_star_" + name]) for name, _, _, _ in WALL_PROBES]
        ax.plot(times, [y for _, y, _, _ in WALL_PROBES], "o-", ms=4, lw=1, label="unisph, " + label)
        print("%-22s %s" % (label, "  ".join("%s %.3f" % (n, c) for (n, _, _, _), c in zip(WALL_PROBES, times))))
        drawn = True
    if not drawn:
        plt.close(fig)
        return
    lobovsky = []
    for name, y, data, who in WALL_PROBES:
        c = first_crossing(*read_experiment(data))
        if who.startswith("Buchner"):
            ax.plot(c, y, "ks", ms=8, mfc="none", label="Buchner (2002)")
        else:
            ax.plot(c, y, "k^", ms=8, mfc="none", label=who if name == "wall_0.01H" else None)
            lobovsky.append((c, y))
        print("%-22s %s %.3f" % (who, name, c))
    ax.plot([c for c, _ in lobovsky], [y for _, y in lobovsky], "k:", lw=1)
    ax.plot([2.30, 2.65], [0.2, 0.2], "r-", lw=3, alpha=0.4, label="issue's bound at 0.2 H")
    ax.set_xlabel("first t sqrt(g/H) with p / (rho g H) > 0.2")
    ax.set_ylabel("height on the downstream wall / H")
    ax.set_ylim(0, 0.3)
    ax.set_title("Dam break: arrival of the water at the wall probes")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(images, "sph_dambreak_arrival.png"), dpi=120)


def main():
    root = sys.argv[1]
    images = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "..", "docs", "images")
    os.makedirs(images, exist_ok=True)

    dam = read_observers(os.path.join(root, "dambreak_2d"))
    if dam:
        fig, ax = plt.subplots(figsize=(8, 4))
        ax.plot(dam["time_star"], dam["p_star_wall_0.2H"], lw=0.8, label="unisph, H/dx = 40")
        t, p = read_experiment("buchner_2002_wall_pressure.csv")
        ax.plot(t, p, "k.", ms=4, label="Buchner (2002), 0.2 H")
        for name, label, style in [("lobovsky_2014_sensor1.csv", "Lobovsky et al. (2014), 3 mm", "c+")]:
            t, p = read_experiment(name)
            ax.plot(t, p, style, ms=4, label=label)
        ax.axhline(0.2, color="grey", lw=0.5)
        ax.axvspan(3.5, 5, color="grey", alpha=0.1)
        ax.set_xlim(0, 8)
        ax.set_xlabel("t sqrt(g/H)")
        ax.set_ylabel("p / (rho g H)")
        ax.set_title("2D dam break: pressure on the downstream wall at 0.2 H")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(images, "sph_dambreak_pressure.png"), dpi=120)

        fig, ax = plt.subplots(figsize=(6, 4))
        e0 = dam["kinetic_energy"][0] + dam["potential_energy"][0]
        ax.plot(dam["time_star"], [(k + p) / e0 for k, p in zip(dam["kinetic_energy"], dam["potential_energy"])],
                label="(kinetic + potential) / initial")
        ax.plot(dam["time_star"], [k / e0 for k in dam["kinetic_energy"]], label="kinetic / initial")
        ax.set_xlabel("t sqrt(g/H)")
        ax.set_title("2D dam break: mechanical energy")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(images, "sph_dambreak_energy.png"), dpi=120)

    pressure_profile(root, images)
    arrival_at_probes(root, images)

    col = read_observers(os.path.join(root, "column_collapse_2d"))
    if col:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(col["time_star"], col["front_star"], label="unisph, L/dx = 40")
        fine = read_observers(os.path.join(root, "column_collapse_2d_dx80"))
        if fine:
            ax.plot(fine["time_star"], fine["front_star"], "--", label="unisph, L/dx = 80")
        for name, label, style in [("martin_moyce_1952_a1.125in.csv", "Martin & Moyce, a = 1.125 in", "ko"),
                                   ("martin_moyce_1952_a2.25in.csv", "Martin & Moyce, a = 2.25 in", "ks"),
                                   ("koshizuka_oka_1996_experiment.csv", "Koshizuka & Oka", "r^")]:
            t, z = read_experiment(name)
            ax.plot(t, z, style, ms=4, mfc="none", label=label)
        ax.set_xlabel("T = t sqrt(2g/L)")
        ax.set_ylabel("z / L")
        ax.set_xlim(0, 3)
        ax.set_title("Collapsing column: surge front")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(images, "sph_column_collapse_front.png"), dpi=120)

    hyd = read_observers(os.path.join(root, "hydrostatic_2d"))
    if hyd:
        fig, ax = plt.subplots(figsize=(6, 4))
        for depth in ["0.25H", "0.5H", "0.75H"]:
            ax.plot(hyd["time_star"], hyd["p_star_depth_" + depth], lw=0.8, label="probe at depth " + depth)
            ax.axhline(float(depth[:-1]), color="grey", lw=0.5)
        ax.set_xlabel("t sqrt(g/H)")
        ax.set_ylabel("p / (rho g H)")
        ax.set_title("Hydrostatic tank: kernel-averaged probes")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(images, "sph_hydrostatic_probes.png"), dpi=120)


if __name__ == "__main__":
    main()
