#!/usr/bin/env /usr/bin/python3
"""The 2D dam break in the short and in the general form: the 0.2 H wall probe and the front
against time, from two runs' observers.csv (docs/sph.md, "The general form").

    scripts/plot_general_form.py SHORT_DIR GENERAL_DIR OUT.png
(SHORT_DIR, GENERAL_DIR: output folders of `unisph run cases/dambreak_2d.toml` and of
`unisph run cases/dambreak_general_2d.toml`.)"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def series(folder):
    lines = [l for l in open(folder + "/observers.csv") if not l.startswith("#")]
    rows = list(csv.reader(lines))
    head, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
    column = lambda name: [r[head.index(name)] for r in data]
    return column("time_star"), column("p_star_wall_0.2H"), column("front_star")


def main():
    short_dir, general_dir, out = sys.argv[1:4]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    for folder, label, style in ((short_dir, "short form (tank wall on a fitted spacing)", "-"),
                                 (general_dir, "general form (shapes; far wall on the lattice)", "--")):
        t, p, front = series(folder)
        ax1.plot(t, p, style, lw=1, label=label)
        ax2.plot(t, front, style, lw=1, label=label)
    ax1.set_xlabel("t sqrt(g/H)")
    ax1.set_ylabel("p / (rho g H) at 0.2 H on the far wall")
    ax1.set_xlim(0, 8)
    ax1.legend(fontsize=8)
    ax2.set_xlabel("t sqrt(g/H)")
    ax2.set_ylabel("front x / H")
    ax2.set_xlim(0, 3)
    ax2.legend(fontsize=8)
    fig.suptitle("2D dam break at H/40, par, double: the short and the general form")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
