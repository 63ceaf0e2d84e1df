#!/usr/bin/env bash
# One device call for the neighbour search (docs/neighbor_search.md): the GPU tests, the
# kernels' resource usage, the density pass by direct search and by the stored lists that
# cache each pair's geometry (fixed slots, slot-major on the device, built by one search),
# the list and cell-list builds, and Nsight Compute profiles of the two kernels that miss
# issue 3's targets (the direct density pass in Morton order, with the cell-order pass beside
# it, and the cell-list build in random order). Run from the repository root on the GPU
# machine with the bundle made by
#   ../shared/tools/device-bundle devbundle-nbopt build/nbopt-cuda/bench/neighbor/neighbor_bench \
#     build/nbopt-cuda/tests/neighbor/test_neighbor_relation build/nbopt-cuda/tests/neighbor/test_cell_linked_list \
#     build/nbopt-cuda/tests/neighbor/test_particle_sorter
# Writes everything under $OUT and prints a short table last. Each stage has a time limit so
# that the whole stays under 8 minutes (3 x 60 + 210 + 3 x 55 s at most). The profile filters
# end in "/": benchmark names go on with /min_time:.../real_time, so a filter ending in "$"
# (as here until 2026-11-21) matched nothing and profiled nothing.
set -u
B=devbundle-nbopt/run
OUT=${OUT:-/tmp/nbopt}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
for t in test_neighbor_relation test_cell_linked_list test_particle_sorter; do
  timeout 60 $B $t --gtest_filter='*/gpu.*' > "$OUT/$t.log" 2>&1
  echo "$t rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$OUT/$t.log" | tr '\n' ' ')"
done
cuobjdump -res-usage devbundle-nbopt/bin/neighbor_bench > "$OUT/neighbor_bench.res" 2>&1
dev='ParallelDevicePolicy'
direct="DensityPass<$dev, SearchMethod::direct>/n:(4|10)000000/order:[02]/split:[12]"
stored="(DensityPass<$dev, SearchMethod::stored>|StoredListBuild<$dev>)/n:(4|10)000000/order:[02]/split:[12]"
build="CellListBuild<$dev>/n:10000000/order:[012]/split:1"
timeout 210 $B neighbor_bench --benchmark_filter="($direct|$stored|$build)" \
  --benchmark_repetitions=2 --benchmark_format=json --benchmark_out="$OUT/nb.json" > "$OUT/nb.txt" 2>&1
echo "neighbor_bench rc=$?"
# Profiles: one launch each, the clocks left alone (METHOD.md).
prof() {  # name, kernel regex, launches to skip, launches, benchmark filter
  timeout 55 ncu --clock-control none --kernel-name-base demangled -k "regex:$2" --launch-skip "$3" --launch-count "$4" \
    --section SpeedOfLight --section MemoryWorkloadAnalysis --section Occupancy --section WarpStateStats \
    --section LaunchStats --section SchedulerStats \
    $B neighbor_bench --benchmark_filter="$5" > "$OUT/ncu_$1.txt" 2>&1
  echo "ncu $1 rc=$? $(grep -E 'Duration|Memory Throughput|Achieved Occupancy' "$OUT/ncu_$1.txt" | head -3 | tr -s ' ' | tr '\n' ';')"
}
prof pass_morton 'DensitySummation' 2 1 "DensityPass<$dev, SearchMethod::direct>/n:4000000/order:0/split:2/"
prof pass_cell 'DensitySummation' 2 1 "DensityPass<$dev, SearchMethod::direct>/n:4000000/order:2/split:2/"
prof build_random 'cell_list_detail|scan|Scan' 0 6 "CellListBuild<$dev>/n:10000000/order:1/split:1/"
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
for b in json.load(open(f"{out}/nb.json"))["benchmarks"]:
    if b.get("run_type") == "aggregate": continue
    name = b["name"].replace("ParallelDevicePolicy", "dev").replace("SearchMethod::", "").split("/min_time")[0]
    print(name, round(b["real_time"], 3), round(b.get("ms_per_1e6", 0), 3), round(b.get("mean_density", 0), 5))
PY
