#!/usr/bin/python3
"""Wave heights and periods at a flume's gauges against linear theory (Debian's numpy: run with
/usr/bin/python3). The method of docs/validation.md ("Piston and flap flumes at k d = 1"):

    scripts/wave_heights.py OBSERVERS.csv PERIOD HEIGHT GROUP_VELOCITY NAME=X [NAME=X ...]
        [--ramp-periods 2] [--periods 5]

For each gauge NAME (the column gauge_NAME of observers.csv) at distance X from the paddle: the
window of PERIODS periods that starts when the ramp's tail has passed the gauge (t = X /
GROUP_VELOCITY + RAMP_PERIODS * PERIOD); the wave height is twice the amplitude of the
least-squares sinusoid of the known PERIOD (with a mean) over the window, given with its
difference from HEIGHT in %; the period is the best-fitting one (the least residual of such
sinusoids over 0.8 .. 1.2 PERIOD, as the flume's validation test does). A window that runs past
the end of the series is an error naming the gauge.
"""
import argparse
import sys

import numpy as np

from observer_csv import read_columns


def fail(message):
    sys.stderr.write("wave_heights.py: " + message + "\n")
    sys.exit(1)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("observers")
    p.add_argument("period", type=float)
    p.add_argument("height", type=float)
    p.add_argument("group_velocity", type=float)
    p.add_argument("gauges", nargs="+", help="NAME=X: gauge_NAME's column, X its distance from the paddle")
    p.add_argument("--ramp-periods", type=float, default=2.0)
    p.add_argument("--periods", type=float, default=5.0)
    a = p.parse_args()
    header, columns = read_columns(a.observers, fail)
    t = np.array(columns["time"])
    w = 2 * np.pi / a.period
    print("gauge, x, window, height, % of theory, period, % of the paddle's")
    for spec in a.gauges:
        name, _, x = spec.partition("=")
        column = "gauge_" + name
        if column not in header or not x:
            fail(f"{a.observers}: no column '{column}' (or no X in '{spec}')")
        start = float(x) / a.group_velocity + a.ramp_periods * a.period
        end = start + a.periods * a.period
        if end > t[-1] + 1e-9:
            fail(f"{a.observers}: gauge {name}'s window {start:.2f} .. {end:.2f} runs past the series' end {t[-1]:.2f}")
        m = (t >= start) & (t <= end)
        tt, eta = t[m], np.array(columns[column])[m]
        def fit(omega):
            basis = np.column_stack([np.sin(omega * tt), np.cos(omega * tt), np.ones_like(tt)])
            coef, residual = np.linalg.lstsq(basis, eta, rcond=None)[:2]
            return coef, (residual[0] if len(residual) else 0.0)

        coef = fit(w)[0]
        height = 2 * np.hypot(coef[0], coef[1])
        factors = np.arange(0.8, 1.2 + 1e-12, 1e-4)
        period = a.period * factors[int(np.argmin([fit(w / f)[1] for f in factors]))]
        print(f"{name}, {float(x):.4f}, {start:.2f} .. {end:.2f}, {height:.5f}, {100 * (height / a.height - 1):+.1f}, "
              f"{period:.4f}, {100 * (period / a.period - 1):+.2f}")


if __name__ == "__main__":
    main()
