#!/usr/bin/env python3
"""Markdown table of a neighbor_bench JSON file (medians when the run has aggregates).

    scripts/neighbor_bench_table.py bench/neighbor/results/2026-11-24-h100-issue3-table.json
"""
import json
import re
import sys

ORDERS = {"0": "Morton", "1": "random", "2": "cell order", "3": "Morton, visited cell by cell",
          "4": "Morton, through the cell-ordered copy"}
STEPS = {"CellListBuild": "cell-list build", "StoredListBuild": "stored-list build",
         "MortonSort": "Morton sort (keys + radix sort + permute 4 variables)"}
POLICIES = {"ParallelDevicePolicy": "device", "ParallelPolicy": "par", "SequencedPolicy": "seq"}


def rows(benchmarks):
    have_aggregates = any(b.get("run_type") == "aggregate" for b in benchmarks)
    for b in benchmarks:
        if have_aggregates and b.get("aggregate_name") != "median":
            continue
        m = re.match(r"BM_(\w+)<(\w+)(?:, SearchMethod::(\w+))?>/(?:n:)?(\d+)(?:/order:(\d)/split:(\d))?", b["name"])
        if not m:
            continue
        kind, policy, method, n, order, split = m.groups()
        step = STEPS.get(kind, f"density pass, {method}")
        yield (kind, policy, method or "", int(n), order or "", split or ""), step, b


def main(path):
    data = json.load(open(path))
    print("| policy | step | particles | order | cells | ms per call | ms per 10^6 | candidate pairs/s | neighbour pairs/s |")
    print("|---|---|---:|---|---|---:|---:|---:|---:|")
    for key, step, b in sorted(rows(data["benchmarks"]), key=lambda r: r[0]):
        kind, policy, _, n, order, split = key
        pairs = kind in ("DensityPass", "StoredListBuild")
        rate = lambda name: f"{b[name] / 1e9:.1f} G" if pairs and b.get(name) else ""
        per = b.get("ms_per_1e6")
        print(f"| {POLICIES.get(policy, policy)} | {step} | {int(b.get('particles', n)):,} | "
              f"{ORDERS.get(order, 'random → sorted')} | {dict(zip('12', ['cutoff', 'cutoff / 2'])).get(split, '')} | "
              f"{b['real_time']:.3f} | {f'{per:.3f}' if per else ''} | {rate('candidate_pairs/s')} | {rate('neighbor_pairs/s')} |")


if __name__ == "__main__":
    main(sys.argv[1])
