#!/usr/bin/python3
"""Figures of `unisph run` observer files (observers.csv), for docs/validation.md.

    sph_run_metrics.py crossing  RUN.csv [PROBE]          first time p* > 0.2, mean p* over [3.5, 5]
    sph_run_metrics.py arrivals  RUN.csv                  first time p* > 0.2 at every wall probe
    sph_run_metrics.py front     A.csv B.csv [T_MAX]      largest |front_A - front_B| / front_B for t* <= T_MAX
    sph_run_metrics.py moved     FIRST.vtp LAST.vtp DX    share of the particles (by ParticleId) that moved less than DX
    sph_run_metrics.py summary   RUN.csv                  every wall probe: crossing, window mean, noise, lowest value before the impact
    sph_run_metrics.py noise     FILE.csv COLUMN...       the pressure noise of columns of any CSV with a t_star / time_star column

The pressure noise (issue 23): p* sampled every 0.01 in t* (linear interpolation), minus its
centred moving average over 0.25 (25 samples), its standard deviation over t* in [3.5, 5].
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


def resample(t, y, step=0.01):
    """y at t0, t0 + step, ... (linear interpolation), from the first multiple of step in range."""
    import math
    k0, k1 = math.ceil(t[0] / step - 1e-9), math.floor(t[-1] / step + 1e-9)
    out, j = [], 1
    for k in range(k0, k1 + 1):
        x = k * step
        while j < len(t) - 1 and t[j] < x:
            j += 1
        a, b = t[j - 1], t[j]
        w = (x - a) / (b - a) if b > a else 0.0
        out.append((x, y[j - 1] + w * (y[j] - y[j - 1])))
    return out


def pressure_noise(t, y, a=3.5, b=5.0, step=0.01, width=0.25):
    """Standard deviation over [a, b] of y minus its centred moving average over `width`."""
    s = resample(t, y, step)
    half = int(round(width / step)) // 2  # 25 samples: 12 either side (0.24 wide)
    res = []
    for k in range(half, len(s) - half):
        x = s[k][0]
        if a - 1e-9 <= x <= b + 1e-9:
            avg = sum(v for _, v in s[k - half:k + half + 1]) / (2 * half + 1)
            res.append(s[k][1] - avg)
    m = sum(res) / len(res)
    return (sum((r - m) ** 2 for r in res) / len(res)) ** 0.5


def lowest_before(t, y, tmax):
    """The lowest value of y for t < tmax (the dip before the impact)."""
    vals = [v for x, v in zip(t, y) if x < tmax]
    return min(vals) if vals else float("nan")


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
    elif what == "summary":
        d = read(sys.argv[2])
        t = d["time_star"]
        names = sorted((k for k in d if k.startswith("p_star_wall_")), key=lambda k: (len(k), k))
        print("%-12s %9s %9s %9s %9s" % ("probe", "crossing", "mean", "noise", "dip"))
        for name in names:
            c = first_crossing(t, d[name])
            mean = window_mean(t, d[name], 3.5, 5.0) if t[-1] >= 5 else float("nan")
            noise = pressure_noise(t, d[name]) if t[-1] >= 5.13 else float("nan")
            dip = lowest_before(t, d[name], c if c is not None else t[-1])
            print("%-12s %9.4f %9.4f %9.4f %9.4f" % (name[len("p_star_wall_"):], c if c else float("nan"), mean, noise, dip))
    elif what == "noise":
        d = read(sys.argv[2])
        t = d["t_star"] if "t_star" in d else d["time_star"]
        for name in sys.argv[3:]:
            print("%-12s noise %.4f mean %.4f" % (name, pressure_noise(t, d[name]), window_mean(t, d[name], 3.5, 5.0)))
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
