#!/usr/bin/python3
"""Stiffness of a particle lattice under the SPH pair pressure force in a uniform pressure p.

The momentum equation a_i = -(1/rho_i) sum_j (p_i + p_j) grad W_ij V_j, linearised about a
lattice in a uniform pressure p for a plane wave u e^{ik.x}, gives
    u'' = -(2 p / (rho dx^2)) Lambda(k) u,   Lambda(k) = dx^4 sum_j H(x_j) (1 - cos k.x_j),
with H the Hessian of the 2D Wendland C2 kernel, W'' e e^T + (W'/r)(I - e e^T). A negative
eigenvalue of Lambda is a mode that grows at sqrt(2 |Lambda| p / rho) / dx whatever the sound
speed (docs/validation.md, "The hydrostatic tank's instability").

Prints the smallest eigenvalue over the Brillouin zone for the square lattice at several h/dx
and for two other lattices of the same density at h = 1.3 dx, and checks the figures the
documentation quotes. Exit status 0 when they hold.
"""
import math
import sys


def kernel(h):
    alpha = 7.0 / (4.0 * math.pi * h * h)

    def d1(r):  # dW/dr
        q = r / h
        if q >= 2:
            return 0.0
        t = 1 - 0.5 * q
        return -5.0 * q * t ** 3 * alpha / h

    def d2(r):  # d2W/dr2
        q = r / h
        if q >= 2:
            return 0.0
        t = 1 - 0.5 * q
        return alpha / (h * h) * t * t * (10.0 * q - 5.0)

    return d1, d2


def smallest_eigenvalue(h, a1, a2, samples=25):
    """Smallest eigenvalue of Lambda(k) over k.a1, k.a2 in [0, 2 pi] (dx = 1)."""
    d1, d2 = kernel(h)
    neighbours = []
    for i in range(-6, 7):
        for j in range(-6, 7):
            x = (i * a1[0] + j * a2[0], i * a1[1] + j * a2[1])
            r = math.hypot(*x)
            if 0 < r < 2 * h:
                e = (x[0] / r, x[1] / r)
                t = d1(r) / r
                l = d2(r)
                hxx = l * e[0] * e[0] + t * (1 - e[0] * e[0])
                hyy = l * e[1] * e[1] + t * (1 - e[1] * e[1])
                hxy = (l - t) * e[0] * e[1]
                neighbours.append((x, hxx, hyy, hxy))
    det = a1[0] * a2[1] - a1[1] * a2[0]
    worst = (math.inf, None)
    for s in range(samples):
        for u in range(samples):
            f1, f2 = 2 * math.pi * s / (samples - 1), 2 * math.pi * u / (samples - 1)
            # k with k.a1 = f1, k.a2 = f2
            k = ((f1 * a2[1] - f2 * a1[1]) / det, (a1[0] * f2 - a2[0] * f1) / det)
            xx = yy = xy = 0.0
            for x, hxx, hyy, hxy in neighbours:
                c = 1 - math.cos(k[0] * x[0] + k[1] * x[1])
                xx += c * hxx
                yy += c * hyy
                xy += c * hxy
            low = 0.5 * (xx + yy) - math.sqrt(0.25 * (xx - yy) ** 2 + xy * xy)
            if low < worst[0]:
                worst = (low, k)
    return worst


def main():
    ok = True
    square = ((1.0, 0.0), (0.0, 1.0))
    print("square lattice, smallest eigenvalue of Lambda (dx = 1) and where:")
    figures = {}
    for h in (1.1, 1.2, 1.3, 1.4, 1.6, 1.8, 2.0):
        value, k = smallest_eigenvalue(h, *square)
        figures[h] = value
        print("  h/dx = %.1f: %+.4f at k = (%.2f, %.2f)" % (h, value, k[0], k[1]))
    # The figures docs/validation.md quotes.
    ok &= abs(figures[1.3] + 0.0311) < 5e-4
    ok &= figures[2.0] > -1e-9
    staggered = smallest_eigenvalue(1.3, (1.0, 0.0), (0.5, 1.0))[0]
    s = math.sqrt(2 / math.sqrt(3))
    hexagonal = smallest_eigenvalue(1.3, (s, 0.0), (s / 2, s * math.sqrt(3) / 2))[0]
    print("h/dx = 1.3, every other row offset by dx/2: %+.4f; hexagonal, same density: %+.4f" % (staggered, hexagonal))
    ok &= staggered > -1e-9 and hexagonal > -1e-9
    growth = [math.sqrt(2 * -figures[1.3] * 1.0) / dx for dx in (0.05, 0.025)]
    print("growth rate at p = rho g H = 1: H/20 %.1f, H/40 %.1f per unit of t sqrt(g/H)" % tuple(growth))
    print("figures as documented" if ok else "FIGURES DIFFER FROM THE DOCUMENTATION")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
