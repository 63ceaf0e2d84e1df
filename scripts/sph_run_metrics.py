#!/usr/bin/python3
"""Figures of `unisph run` observer files (observers.csv), for docs/validation.md.

    sph_run_metrics.py crossing  RUN.csv [PROBE]          first time p* > 0.2, mean p* over [3.5, 5]
    sph_run_metrics.py arrivals  RUN.csv                  first time p* > 0.2 at every wall probe
    sph_run_metrics.py front     A.csv B.csv [T_MAX]      largest |front_A - front_B| / front_B for t* <= T_MAX
    sph_run_metrics.py moved     FIRST.vtp LAST.vtp DX    share of the particles (by ParticleId) that moved less than DX
"""
import csv
import sys


def read(path):
    with open(path) as f:
        rows = [r for r in f if not r.startswith("#")]
    cols = {}
    for row in csv.DictReader(rows):
        for k, v in row.items():
            cols.setdefault(k, []).append(float(v))
    return cols


def interp(t, y, x):
    for k in range(1, len(t)):
        if t[k - 1] <= x <= t[k]:
            w = (x - t[k - 1]) / (t[k] - t[k - 1]) if t[k] > t[k - 1] else 0
            return y[k - 1] + w * (y[k] - y[k - 1])
    return None


def window_mean(t, y, a, b):
    xs = [a] + [x for x in t if a < x < b] + [b]
    s = sum(0.5 * (interp(t, y, xs[k - 1]) + interp(t, y, xs[k])) * (xs[k] - xs[k - 1]) for k in range(1, len(xs)))
    return s / (b - a)


def first_crossing(t, y, level=0.2):
    """The first time y exceeds level, interpolated linearly from the sample before (None if never)."""
    for k in range(1, len(t)):
        if y[k] > level:
            return t[k - 1] + (level - y[k - 1]) / (y[k] - y[k - 1]) * (t[k] - t[k - 1])
    return None


def main():
    what = sys.argv[1]
    if what == "crossing":
        d = read(sys.argv[2])
        probe = sys.argv[3] if len(sys.argv) > 3 else "wall_0.2H"
        t, p = d["time_star"], d["p_star_" + probe]
        crossing = first_crossing(t, p)
        mean = window_mean(t, p, 3.5, 5.0) if t[-1] >= 5 else float("nan")
        print("crossing %.4f window_mean %.4f" % (crossing if crossing else float("nan"), mean))
    elif what == "arrivals":
        d = read(sys.argv[2])
        for name in sorted((k for k in d if k.startswith("p_star_")), key=lambda k: float(k.split("_")[-1][:-1])):
            c = first_crossing(d["time_star"], d[name])
            print("%-16s %s" % (name[len("p_star_"):], "%.3f" % c if c is not None else "never"))
    elif what == "front":
        a, b = read(sys.argv[2]), read(sys.argv[3])
        tmax = float(sys.argv[4]) if len(sys.argv) > 4 else 1e30
        worst = 0
        for t, f in zip(a["time_star"], a["front"]):
            if t > tmax:
                break
            g = interp(b["time_star"], b["front"], t)
            if g:
                worst = max(worst, abs(f - g) / g)
        print("largest front difference %.4f %%" % (100 * worst))
    elif what == "moved":
        import vtk  # Debian's python3-vtk9
        from vtk.util.numpy_support import vtk_to_numpy

        def by_id(path):
            r = vtk.vtkXMLPolyDataReader()
            r.SetFileName(path)
            r.Update()
            out = r.GetOutput()
            ids = vtk_to_numpy(out.GetPointData().GetArray("ParticleId"))
            x = vtk_to_numpy(out.GetPoints().GetData())
            return {int(i): x[k] for k, i in enumerate(ids)}

        a, b, dx = by_id(sys.argv[2]), by_id(sys.argv[3]), float(sys.argv[4])
        still = sum(1 for i, x in a.items() if sum((x - b[i]) ** 2) ** 0.5 < dx)
        print("%.2f %% of %d particles moved less than dx" % (100.0 * still / len(a), len(a)))


if __name__ == "__main__":
    main()
