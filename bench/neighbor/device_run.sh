#!/usr/bin/env bash
# One device call for the neighbour-search optimisation (docs/neighbor_search.md): the GPU
# tests, the kernels' resource usage, and the density-pass variants. Run from the repository
# root on the GPU machine with the bundle made by
#   /work/shared/tools/device-bundle devbundle-nbopt build/<cuda>/bench/neighbor/neighbor_bench \
#     build/<cuda>/tests/neighbor/test_neighbor_relation build/<cuda>/tests/neighbor/test_cell_linked_list \
#     build/<cuda>/tests/neighbor/test_particle_sorter
# Writes everything under $OUT and prints a short table last.
set -u
B=devbundle-nbopt/run
OUT=${OUT:-/tmp/nbopt}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
for t in test_neighbor_relation test_cell_linked_list test_particle_sorter; do
  $B $t --gtest_filter='*/gpu.*' > "$OUT/$t.log" 2>&1
  echo "$t rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$OUT/$t.log" | tr '\n' ' ')"
done
for b in neighbor_bench; do
  cuobjdump -res-usage devbundle-nbopt/bin/$b > "$OUT/$b.res" 2>&1
done
direct='DensityPass<ParallelDevicePolicy, SearchMethod::direct>/n:(1|4|10)000000/order:[02]'
stored='(DensityPass<ParallelDevicePolicy, SearchMethod::stored>|StoredListBuild<ParallelDevicePolicy>)/n:(4|10)000000/order:[02]/split:[12]'
$B neighbor_bench --benchmark_filter="($direct|$stored|CellListBuild<ParallelDevicePolicy>/n:10000000)" \
  --benchmark_repetitions=2 --benchmark_format=json --benchmark_out="$OUT/nb.json" > "$OUT/nb.txt" 2>&1
echo "neighbor_bench rc=$?"
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
for f in ("nb.json",):
    for b in json.load(open(f"{out}/{f}"))["benchmarks"]:
        if b.get("run_type") == "aggregate": continue
        name = b["name"].replace("ParallelDevicePolicy", "dev").replace("SearchMethod::", "").split("/min_time")[0]
        print(f[:-5], name, round(b["real_time"], 3), round(b.get("ms_per_1e6", 0), 3),
              round(b.get("mean_density", 0), 5))
PY
