#!/usr/bin/python3
"""Plot the residual history that `unisph generate` writes (FILE_residual.csv).

Usage: /usr/bin/python3 scripts/plot_relaxation.py FILE_residual.csv [FILE_residual.png]

The mean and largest zero-order consistency error |sum_j grad W_ij V_j + G(x_i)| h against the
iteration, on a log scale. Uses Debian's matplotlib (python3-matplotlib), hence /usr/bin/python3.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: plot_relaxation.py FILE_residual.csv [FILE_residual.png]")
    source = sys.argv[1]
    target = sys.argv[2] if len(sys.argv) == 3 else os.path.splitext(source)[0] + ".png"
    iteration, mean, largest = [], [], []
    with open(source, newline="") as f:
        for line, row in enumerate(csv.DictReader(f), start=2):
            try:
                iteration.append(int(row["iteration"]))
                mean.append(float(row["mean_error"]))
                largest.append(float(row["max_error"]))
            except (KeyError, TypeError, ValueError) as e:
                sys.exit(f"{source}: line {line}: expected iteration,mean_error,max_error,step ({e})")
    if not iteration:
        sys.exit(f"{source}: no rows")
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.semilogy(iteration, largest, label="largest")
    ax.semilogy(iteration, mean, label="mean")
    ax.set_xlabel("iteration")
    ax.set_ylabel(r"$|\sum_j \nabla W_{ij} V_j + G_i|\,h$")
    ax.set_title(os.path.basename(source).replace("_residual.csv", "") + ": zero-order consistency error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    tmp = target + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, target)


if __name__ == "__main__":
    main()
