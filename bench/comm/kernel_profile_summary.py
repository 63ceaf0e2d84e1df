#!/usr/bin/env python3
"""Per-kernel device time from bench/comm/device_kernel_profile.sh's Nsight Compute logs.

    kernel_profile_summary.py OUT [--detail]

For each log OUT/<run>.rank<r>.csv: every kernel family's calls and milliseconds (the functor a
launch wrapper runs, or CUB's kernel, namespaces and template arguments dropped; --detail keeps
the functor's own template arguments), the families sorted by the first log's time."""
import csv
import glob
import os
import re
import sys
from collections import defaultdict

WRAPPERS = ("particle_for_kernel", "particle_for_kernel_hinted", "reduce_blocks", "reduce_partials",
            "tree_reduce_level", "collective_kernel", "team_kernel")
UNITS = {"nsecond": 1e-6, "usecond": 1e-3, "msecond": 1.0, "second": 1e3}


def split_top(s):
    """Top-level template arguments of s's first <...>, and the name before it."""
    at = s.find("<")
    if at < 0:
        return s, []
    depth, args, start = 0, [], at + 1
    for k in range(at, len(s)):
        c = s[k]
        if c == "<":
            depth += 1
        elif c == ">":
            depth -= 1
            if depth == 0:
                args.append(s[start:k].strip())
                return s[:at], args
        elif c == "," and depth == 1:
            args.append(s[start:k].strip())
            start = k + 1
    return s[:at], args


def strip_templates(s):
    out, depth = [], 0
    for c in s:
        if c == "<":
            depth += 1
        elif c == ">":
            depth -= 1
        elif depth == 0:
            out.append(c)
    return "".join(out)


def family(name, detail):
    name = re.sub(r"^void ", "", name.strip())
    depth = 0
    for k, c in enumerate(name):  # cut the parameter list
        if c in "<":
            depth += 1
        elif c == ">":
            depth -= 1
        elif c == "(" and depth == 0:
            name = name[:k]
            break
    head, args = split_top(name)
    if head.split("::")[-1] in WRAPPERS:
        for a in args:
            if "unisph" in a or "::" in a:
                name = a
                break
    if detail:
        base = strip_templates(name.split("<", 1)[0]).split("::")
        inner = name[len(name.split("<", 1)[0]):]
        return "::".join(base[-2:]) + re.sub(r"unisph::[a-z_:]*", "", inner)[:80]
    parts = [p for p in strip_templates(name).split("::") if p]
    return "::".join(parts[-2:]) if parts else name


def read(path, detail):
    times, calls = defaultdict(float), defaultdict(int)
    with open(path, newline="") as f:
        lines = [l for l in f if l.startswith('"')]
    rows = list(csv.reader(lines))
    if not rows:
        return times, calls
    header = rows[0]
    ki, ti = header.index("Kernel Name"), header.index("gpu__time_duration.sum")
    scale = 1e-6
    for row in rows[1:]:
        if len(row) <= max(ki, ti):
            continue
        if row[0] == "":  # the units row
            scale = UNITS.get(row[ti], 1e-6)
            continue
        try:
            t = float(row[ti].replace(",", "")) * scale
        except ValueError:
            continue
        key = family(row[ki], detail)
        times[key] += t
        calls[key] += 1
    return times, calls


def main():
    out = sys.argv[1]
    detail = "--detail" in sys.argv
    logs = sorted(glob.glob(os.path.join(out, "*.rank*.csv")))
    data = [(os.path.basename(p)[:-4], *read(p, detail)) for p in logs]
    if not data:
        sys.exit("no logs in " + out)
    keys = sorted({k for _, t, _ in data for k in t}, key=lambda k: -max(t.get(k, 0) for _, t, _ in data))
    w = max(len(k) for k in keys)
    print(f"{'kernel family':{w}}  " + "  ".join(f"{n[:18]:>18}" for n, _, _ in data))
    print(f"{'':{w}}  " + "  ".join(f"{'calls':>7} {'ms':>10}" for _ in data))
    for k in keys:
        print(f"{k:{w}}  " + "  ".join(f"{c.get(k, 0):7d} {t.get(k, 0):10.2f}" for _, t, c in data))
    print(f"{'total':{w}}  " + "  ".join(f"{sum(c.values()):7d} {sum(t.values()):10.2f}" for _, t, c in data))


if __name__ == "__main__":
    main()
