#!/usr/bin/env python3
"""Table of medians from views_bench JSON (run with --benchmark_repetitions=N --benchmark_format=json).

Usage: views_bench_report.py [--seq-cpu-time] views.json [more.json ...]
--seq-cpu-time: the seq rows from the process's CPU time instead of wall-clock time (on a
machine shared with other jobs, where a single-threaded loop gets only part of a core; the par
and device rows stay wall-clock, the only time that counts for them).
Prints one Markdown row per case and policy: the median time of the hand-written loop, of the
view's iterator loop, of View::for_each and, where the case has them, of the engine's direct
neighbour search ("direct"), of the engine's data_point_for ("engine"), of a plain per-package
loop ("plain") and of a CUDA block per package ("team"), their ratios to the hand
loop (and for_each / direct), and whether all checksums of the case agree.
"""
import json
import statistics
import sys
from collections import defaultdict


def main(args):
    seq_cpu = "--seq-cpu-time" in args
    paths = [a for a in args if a != "--seq-cpu-time"]
    times = defaultdict(list)
    checksums = defaultdict(set)
    context = {}
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context = data.get("context", context)
        for b in data["benchmarks"]:
            if b.get("run_type") != "iteration" or b.get("error_occurred"):
                continue
            name = b["run_name"] if "run_name" in b else b["name"]
            name = name.split("/real_time")[0]
            case, loop, policy = name.split("/")[:3]
            key = "cpu_time" if seq_cpu and policy == "seq" else "real_time"
            times[(case, policy, loop)].append(b[key] * {"ms": 1e-3, "us": 1e-6, "ns": 1e-9}[b["time_unit"]])
            checksums[(case, policy)].add(b.get("checksum"))
    print(f"host: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
          f"unisph_host_threads={context.get('unisph_host_threads', '?')}, gpu: {context.get('unisph_gpu', '?')}"
          + (", seq rows: CPU time" if seq_cpu else ""))
    print()
    loops = [l for l in ("view", "for_each", "nested", "direct", "engine", "plain", "team") if any(k[2] == l for k in times)]
    head = ["case", "policy", "reps", "hand (ms)"]
    for loop in loops:
        head += [f"{loop} (ms)", f"{loop} / hand"]
    if "direct" in loops:
        head += ["for_each / direct"]
    head += ["checksums equal"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for case, policy in sorted({(c, p) for c, p, _ in times}):
        hand = times.get((case, policy, "hand"), [])
        if not hand:
            continue
        mh = statistics.median(hand)
        row = [case, policy, str(len(hand)), f"{mh * 1e3:.3f}"]
        for loop in loops:
            t = times.get((case, policy, loop), [])
            if t:
                m = statistics.median(t)
                row += [f"{m * 1e3:.3f}", f"{m / mh:.3f}"]
            else:
                row += ["", ""]
        if "direct" in loops:
            fe, di = times.get((case, policy, "for_each"), []), times.get((case, policy, "direct"), [])
            row += [f"{statistics.median(fe) / statistics.median(di):.3f}" if fe and di else ""]
        same = "yes" if len(checksums[(case, policy)]) == 1 else f"NO {sorted(checksums[(case, policy)])}"
        print("| " + " | ".join(row + [same]) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
