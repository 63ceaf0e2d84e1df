#!/usr/bin/env bash
# One device call for the contiguous-cell walk of the direct search (docs/neighbor_search.md,
# "Morton order without the CSR indirection"): the GPU neighbour tests, then the direct density
# pass and the cell-list build of this tree (neighbor_bench) against the same benchmarks built
# from the commit before it (neighbor_bench_main), interleaved A B A B. Run from the repository
# root on the GPU machine with the bundle made by
#   cp build/base-cuda/bench/neighbor/neighbor_bench /tmp/ab/neighbor_bench_main   # built from main
#   /work/shared/tools/device-bundle devbundle-morton build/morton-cuda/bench/neighbor/neighbor_bench \
#     /tmp/ab/neighbor_bench_main build/morton-cuda/tests/neighbor/test_neighbor_relation \
#     build/morton-cuda/tests/neighbor/test_cell_linked_list build/morton-cuda/tests/neighbor/test_particle_sorter
# (The device tool sends the checkout the session started in, not a helper's worktree: copy the
# bundle and this script into an ignored folder of that checkout, e.g. devbundle-morton/, carry
# it, and run `bash devbundle-morton/device_ab.sh`.) Any further neighbor_bench_* in the bundle
# (a variant under test, e.g. neighbor_bench_flat) is run beside the two.
# Writes results.tar.gz under $OUT (logs and JSON) and prints a short table last (medians; the
# `walk` column needs this tree's benchmark, which reports it).
set -u
B=devbundle-morton/run
OUT=${OUT:-/tmp/morton}
W=$(mktemp -d)
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader | tee "$W/gpu.txt"
for t in test_neighbor_relation test_cell_linked_list test_particle_sorter; do
  timeout 60 $B $t --gtest_filter='*/gpu.*' > "$W/$t.log" 2>&1
  echo "$t rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$W/$t.log" | tr '\n' ' ')"
done
# The variants bundled: main, this tree, and any other neighbor_bench_* (a variant under test).
EXES="neighbor_bench_main neighbor_bench $(cd devbundle-morton/bin && ls neighbor_bench_* | grep -v '^neighbor_bench_main$' | tr '\n' ' ')"
for exe in $EXES; do  # registers of the density kernels
  cuobjdump -res-usage devbundle-morton/bin/$exe 2>&1 | grep -A1 'DensitySummation' | grep -o 'REG:[0-9]*' | sort | uniq -c |
    tr '\n' ' ' | sed "s/^/$exe density kernels: /"; echo
done | tee "$W/registers.txt"
dev='ParallelDevicePolicy'
direct="DensityPass<$dev, SearchMethod::direct>/n:(4|10)000000/order:[02]/split:[12]"
build="CellListBuild<$dev>/n:10000000/order:([012]/split:1|0/split:2)"
for round in 1 2; do
  # The second round only where the first left time for it (the call is limited to 420 s).
  [ $round = 2 ] && [ $SECONDS -gt 200 ] && { echo "round 2 skipped at ${SECONDS} s"; break; }
  for exe in $EXES; do
    timeout 85 $B $exe --benchmark_filter="($direct|$build)" --benchmark_repetitions=3 \
      --benchmark_format=json --benchmark_out="$W/$exe.$round.json" > "$W/$exe.$round.txt" 2>&1
    echo "$exe round $round rc=$? at ${SECONDS} s"
    tar -czf "$OUT/results.tar.gz" -C "$W" .
  done
done
tar -czf "$OUT/results.tar.gz" -C "$W" .
python3 - "$W" <<'PY'
import json, sys, glob, collections
w = sys.argv[1]
rows = collections.defaultdict(dict)
for f in sorted(glob.glob(f"{w}/*.json")):
    exe, rnd = f.split("/")[-1].split(".")[:2]
    try: bs = json.load(open(f))["benchmarks"]
    except Exception as e: print(f, e); continue
    for b in bs:
        if b.get("run_type") != "aggregate" or b.get("aggregate_name") != "median": continue
        name = b["name"].replace("ParallelDevicePolicy", "dev").replace("SearchMethod::", "").split("/min_time")[0].replace("_median", "")
        rows[name][f"{exe.replace('neighbor_bench', 'new').replace('new_main', 'old').replace('new_', '')}{rnd}"] = (b["real_time"], b.get("ms_per_1e6", 0), b.get("mean_density", 0), b.get("walk", -1))
for name, r in rows.items():
    print(name, " ".join(f"{k}:{v[0]:.3f}ms/{v[1]:.3f}" for k, v in sorted(r.items())), "walk", r.get("new1", (0,0,0,-1))[3], "rho", round(r.get("new1", (0,0,0))[2], 5))
PY
