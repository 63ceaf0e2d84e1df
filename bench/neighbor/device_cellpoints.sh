#!/usr/bin/env bash
# One device call (docs/neighbor_search.md, "Morton order with cell-ordered positions"): the GPU
# neighbour tests, then the direct density pass and the cell-list build in Morton order (index
# order, visited in cell order, and visited in cell order through the cell-ordered copy of the
# positions) beside cell order, 4 x 10^6 and 10^7 particles, cells of the cutoff and of half of
# it, medians of 3 repetitions. Run from the repository root on the GPU machine with
#   ../shared/tools/device-bundle devbundle-nb4 build/nb-cuda/bench/neighbor/neighbor_bench \
#     build/nb-cuda/tests/neighbor/test_neighbor_relation build/nb-cuda/tests/neighbor/test_cell_linked_list \
#     build/nb-cuda/tests/neighbor/test_particle_sorter
set -u
B=${BUNDLE:-devbundle-nb4}/run
OUT=${OUT:-/tmp/nb4}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader | tee "$OUT/gpu.txt"
for t in test_neighbor_relation test_cell_linked_list test_particle_sorter; do
  timeout 90 $B $t --gtest_filter='*/gpu.*' > "$OUT/$t.log" 2>&1
  echo "$t rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$OUT/$t.log" | tr '\n' ' ')"
done
dev='ParallelDevicePolicy'
pass="DensityPass<$dev, SearchMethod::direct>/n:(4|10)000000/order:[0234]/split:[12]/"
build="CellListBuild<$dev>/n:10000000/order:[0124]/split:[12]/"
timeout 300 $B neighbor_bench --benchmark_filter="($pass|$build)" --benchmark_enable_random_interleaving=true \
  --benchmark_repetitions=3 --benchmark_format=json --benchmark_out="$OUT/nb.json" > "$OUT/nb.txt" 2>&1
echo "neighbor_bench rc=$?"
python3 - "$OUT" <<'PY'
import json, sys, statistics
out = sys.argv[1]
rows = {}
for b in json.load(open(f"{out}/nb.json"))["benchmarks"]:
    if b.get("run_type") == "aggregate": continue
    name = b["name"].replace("ParallelDevicePolicy", "dev").replace("SearchMethod::", "").split("/min_time")[0]
    rows.setdefault(name, []).append((b["real_time"], b.get("ms_per_1e6", 0), b.get("mean_density", 0)))
for name, v in rows.items():
    print(name, "median ms", round(statistics.median(x[0] for x in v), 4), "ms/1e6", round(statistics.median(x[1] for x in v), 4),
          "density", round(v[0][2], 5))
PY
