#!/usr/bin/env bash
# One device call of an A/B comparison of two sph_bench builds (docs/sph.md, "Neighbour
# records"), run from the repository root on the GPU machine with a bundle made by
#   strip -o /tmp/ab/sph_bench_base <base build>/bench/sph/sph_bench
#   strip -o /tmp/ab/sph_bench_new  <this build>/bench/sph/sph_bench   (and more sph_bench_NAME)
#   strip -o /tmp/ab/test_sph_methods <this build>/tests/sph/test_sph_methods
#   /work/shared/tools/device-bundle /work/main/devbundle-gpu /tmp/ab/* -- cases
# and carried along (carry: devbundle-gpu).
#   bench/sph/ab_device_run.sh CASES ROUNDS [NCU_CASE] [EXTRA]
# CASES: a benchmark filter (e.g. 'SphDamBreak/3D/(0.025|0.0125)/float/gpu'); ROUNDS: rounds of
# the builds named in $BUILDS (default "base new"), interleaved (base, new, base, new, ...), one
# process each; the checkpoints are made by the first run and shared (the same file format). NCU_CASE (a filter naming one case): then a
# Nsight Compute profile of one pressure and one density relaxation pass of the first and the
# last build there (ncu_NAME.txt). EXTRA: more sph_bench options. Writes under $OUT (the JSON of
# the first round); prints a table last.
set -u
B=${BUNDLE:-devbundle-gpu}
OUT=${OUT:-/tmp/sph_ab_out}
CASES=$1
ROUNDS=${2:-2}
NCU=${3:-}
EXTRA=${4:-}
BUILDS=${BUILDS:-base new}
FIRST=${BUILDS%% *}
LAST=${BUILDS##* }
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,memory.total --format=csv,noheader
$B/run test_sph_methods --gtest_filter='*gpu*:*Gpu*:*Device*' > "$OUT/test_sph_methods_gpu.log" 2>&1
echo "test_sph_methods gpu rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$OUT/test_sph_methods_gpu.log" | tr '\n' ' ')"
for r in $(seq 1 "$ROUNDS"); do
  for b in $BUILDS; do
    $B/run sph_bench_$b --sph_cases="$B/data/cases" --sph_cache=/tmp/sph_bench_cache $EXTRA \
      --benchmark_filter="$CASES" --benchmark_format=json --benchmark_out="/tmp/ab_${b}_r$r.json" \
      > /dev/null 2>> "$OUT/sph_bench.err"
    echo "$b round $r rc=$?"
  done
done
grep "made" "$OUT/sph_bench.err"
if [ -n "$NCU" ]; then
  for b in $FIRST $LAST; do
    timeout 150 ncu --clock-control none --kernel-name-base demangled \
      -k 'regex:(PressureRelaxation|DensityRelaxation)<float, 3>::Kernel' --launch-skip 4 --launch-count 2 \
      --section SpeedOfLight --section LaunchStats --section Occupancy --section WarpStateStats \
      --section InstructionStats --section MemoryWorkloadAnalysis --section SchedulerStats \
      $B/bin/sph_bench_$b --sph_cases="$B/data/cases" --sph_cache=/tmp/sph_bench_cache --sph_steps=20 \
      --benchmark_filter="$NCU" > "$OUT/ncu_$b.txt" 2>&1
    echo "ncu $b rc=$? ($NCU)"
  done
fi
python3 - "$OUT" "$ROUNDS" $BUILDS <<'PY'
import json, sys, os
out, rounds, builds = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
rows = {}
for r in range(1, rounds + 1):
    for b in builds:
        path = f"/tmp/ab_{b}_r{r}.json"
        if not os.path.exists(path):
            continue
        data = json.load(open(path))
        if r == 1:
            json.dump(data, open(f"{out}/ab_{b}_r{r}.json", "w"), indent=1)
        for x in data["benchmarks"]:
            if x.get("error_occurred"):
                print(x["name"], b, r, "ERROR", x.get("error_message")); continue
            rows.setdefault(x["name"], []).append((b, r, x))
print("case build round fluid_steps/s pr_ms pr_ms/1e6 neigh/particle bytes/particle")
for name, rs in rows.items():
    for b, r, x in rs:
        print(name, b, r, "%.4e" % x["fluid_steps_per_s"], "%.4f" % x["pressure_relaxation_ms"],
              "%.4f" % x["pressure_relaxation_ms_per_1e6"], "%.1f" % x["neighbors_per_fluid_particle"],
              "%.1f" % x["device_bytes_per_particle"])
PY
