#!/usr/bin/python3
"""Incident and reflected wave heights from two gauges of a `unisph run` observer file (Goda &
Suzuki's two-gauge method; the C++ of it is unisph::two_gauge_reflection, motion/wave_analysis.hpp).

    wave_reflection.py RUN/observers.csv GAUGE1 GAUGE2 SPACING PERIOD DEPTH FROM TO [G]

GAUGE1, GAUGE2: gauge names (columns gauge_<name>), GAUGE2 SPACING further in the direction the
incident wave runs; PERIOD: the wave's; DEPTH: the still water's (gauge readings are levels, the
still level is DEPTH); FROM, TO: the time window (whole periods are best); G: gravity (1).
Each series is fitted with a cos wt + b sin wt + c (least squares, w = 2 pi / PERIOD); with the
complex amplitude Z = a + i b, Z(x) = A e^{ikx} + B e^{-ikx} (k from the dispersion relation)
gives A (incident) and B (reflected) from the two gauges. Prints the heights 2|A|, 2|B| and the
reflection coefficient |B| / |A|. The spacing should lie within 0.05 to 0.45 wavelengths modulo
half a wavelength.
"""
import cmath
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sph_run_metrics as m  # noqa: E402


def wavenumber(period, depth, g):
    """k from w^2 = g k tanh(k d), by Newton's method."""
    w = 2 * math.pi / period
    k = w * w / g if w * w * depth / g > 1 else w / math.sqrt(g * depth)
    for _ in range(100):
        f = g * k * math.tanh(k * depth) - w * w
        df = g * math.tanh(k * depth) + g * k * depth / math.cosh(k * depth) ** 2
        k -= f / df
    return k


def fit(t, y, w):
    """Least squares of y = a cos wt + b sin wt + c: returns a + i b."""
    n = len(t)
    rows = [(math.cos(w * x), math.sin(w * x), 1.0) for x in t]
    ata = [[sum(r[i] * r[j] for r in rows) for j in range(3)] for i in range(3)]
    aty = [sum(r[i] * v for r, v in zip(rows, y)) for i in range(3)]
    # Gaussian elimination on the 3 x 3 normal equations.
    for i in range(3):
        p = max(range(i, 3), key=lambda r: abs(ata[r][i]))
        ata[i], ata[p] = ata[p], ata[i]
        aty[i], aty[p] = aty[p], aty[i]
        for r in range(i + 1, 3):
            f = ata[r][i] / ata[i][i]
            for c in range(i, 3):
                ata[r][c] -= f * ata[i][c]
            aty[r] -= f * aty[i]
    x = [0.0] * 3
    for i in (2, 1, 0):
        x[i] = (aty[i] - sum(ata[i][c] * x[c] for c in range(i + 1, 3))) / ata[i][i]
    assert n > 3
    return complex(x[0], x[1])


def main():
    path, g1, g2 = sys.argv[1], sys.argv[2], sys.argv[3]
    spacing, period, depth, start, end = (float(v) for v in sys.argv[4:9])
    g = float(sys.argv[9]) if len(sys.argv) > 9 else 1.0
    d = m.read(path)
    t = d["time"]
    w = 2 * math.pi / period
    k = wavenumber(period, depth, g)
    pick = [i for i, x in enumerate(t) if start <= x <= end]
    ts = [t[i] for i in pick]
    z1 = fit(ts, [d["gauge_" + g1][i] - depth for i in pick], w)
    z2 = fit(ts, [d["gauge_" + g2][i] - depth for i in pick], w)
    # Z1 = A + B (gauge 1 at x = 0), Z2 = A e^{ik s} + B e^{-ik s}.
    e = cmath.exp(1j * k * spacing)
    det = 1 / e - e
    a = (z1 / e - z2) / det
    b = (z2 - z1 * e) / det
    print("k %.5f, spacing %.3f wavelengths; incident height %.5f, reflected height %.5f, reflection coefficient %.4f"
          % (k, spacing * k / (2 * math.pi), 2 * abs(a), 2 * abs(b), abs(b) / abs(a)))


if __name__ == "__main__":
    main()
