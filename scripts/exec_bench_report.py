#!/usr/bin/python3
"""Turns exec_bench JSON (Google Benchmark) into the markdown tables of docs/benchmarks.md.

usage: scripts/exec_bench_report.py RESULT.json [RESULT.json ...]

For each file: throughput per benchmark and size (the median where repetitions were run), and
the ratios the execution core is judged by:
  GPU: triad and reduce against the device-to-device memcpy at the same N (bytes read + written),
       sort_pairs against cub::DeviceRadixSort::SortPairs called directly;
  CPU: par triad against two plain std::threads, par against seq on the compute-bound kernel.
"""
import json
import re
import sys


def load(path):
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        name = re.sub(r"/(real|manual)_time.*$", "", b["run_name"] if "run_name" in b else b["name"])
        rows[name] = b
    return data["context"], rows


def rate(b):
    if "bytes_per_second" in b and "Scan" not in b["name"]:
        return b["bytes_per_second"] / 1e9, "GB/s"
    return b["items_per_second"] / 1e9, "G items/s"


def report(path):
    context, rows = load(path)
    print(f"### {path}\n")
    print(f"CPU: {context.get('unisph_cpu')} ({context.get('unisph_host_threads')} threads for par); "
          f"GPU: {context.get('unisph_gpu')}; Real = {context.get('unisph_precision')}\n")
    print("| benchmark | N | time per run | throughput |")
    print("|---|---:|---:|---:|")
    for name, b in rows.items():
        value, unit = rate(b)
        n = name.split("/")[-1]
        time_ms = b["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
        print(f"| {name.rsplit('/', 1)[0]} | {n} | {time_ms:.4g} ms | {value:.4g} {unit} |")
    print()
    checks = []

    def ratio(a, b, what, target):
        if a in rows and b in rows:
            x, _ = rate(rows[a])
            y, _ = rate(rows[b])
            checks.append((what, x / y, target))

    big = "100000000"
    ratio(f"Triad<ParallelDevicePolicy>/{big}", f"DeviceMemcpy/{big}", "device triad / memcpy bandwidth, N = 1e8", 0.80)
    ratio(f"Reduce<ParallelDevicePolicy>/{big}", f"DeviceMemcpy/{big}", "device reduce / memcpy bandwidth, N = 1e8", 0.80)
    ratio("SortPairs<ParallelDevicePolicy>/16777216", "CubSortPairs/16777216",
          "device sort_pairs / CUB SortPairs, 2^24 uint32 pairs", 0.90)
    ratio("Triad<ParallelPolicy>/10000000", "TwoThreadTriad/10000000", "par triad / two std::threads, N = 1e7", 0.90)
    ratio("Compute<ParallelPolicy>/1000000", "Compute<SequencedPolicy>/1000000", "par / seq, 64 FMA per item", 1.8)
    if checks:
        print("| check | measured | target | |")
        print("|---|---:|---:|---|")
        for what, value, target in checks:
            print(f"| {what} | {value:.3f} | ≥ {target} | {'met' if value >= target else 'NOT met'} |")
        print()


for p in sys.argv[1:]:
    report(p)
