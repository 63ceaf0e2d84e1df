#!/usr/bin/python3
"""Plots exec_bench throughput against N for each algorithm and policy.

usage: scripts/plot_exec_bench.py RESULT.json OUTPUT.png
"""
import json
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

data = json.load(open(sys.argv[1]))
series = {}
for b in data["benchmarks"]:
    if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
        continue
    m = re.match(r"(\w+)(?:<(\w+)>)?/(\d+)", b.get("run_name", b["name"]))
    if not m:
        continue
    kind, policy, n = m.group(1), m.group(2) or "reference", int(m.group(3))
    if kind in ("Compute", "TwoThreadTriad"):
        continue
    value = b["bytes_per_second"] / 1e9 if kind in ("Triad", "Reduce", "DeviceMemcpy") else b["items_per_second"] / 1e9
    series.setdefault((kind, policy), []).append((n, value))

panels = [("Triad", "GB/s", ["DeviceMemcpy"]), ("Reduce", "GB/s", ["DeviceMemcpy"]), ("Scan", "G items/s", []),
          ("SortPairs", "G keys/s", ["CubSortPairs"])]
fig, axes = plt.subplots(1, 4, figsize=(16, 3.8))
for ax, (kind, unit, refs) in zip(axes, panels):
    for (k, policy), points in sorted(series.items()):
        if k == kind or k in refs:
            points.sort()
            label = f"{policy}" if k == kind else k
            ax.plot([p[0] for p in points], [p[1] for p in points], "o-" if k == kind else "k--", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N")
    ax.set_ylabel(unit)
    ax.set_title(kind)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
ctx = data["context"]
fig.suptitle(f"unisph execution core: GPU {ctx.get('unisph_gpu')}, Real = {ctx.get('unisph_precision')}")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
