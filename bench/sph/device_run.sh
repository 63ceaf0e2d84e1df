#!/usr/bin/env bash
# One device call for the SPH benchmark (docs/sph.md, "Benchmarks"), run from the repository
# root on the GPU machine with the bundle made by
#   /work/shared/tools/device-bundle devbundle-ck build/ck-cuda/bench/sph/sph_bench \
#     build/ck-cuda/tests/sph/test_sph_checkpoint -- cases
# and carried along (carry: devbundle-ck).   bench/sph/device_run.sh [FILTER] [SECONDS] [EXTRA]
# FILTER: the benchmarks (default: every GPU case but the 3D dx 0.00625 ones, whose checkpoint
# at t* = 6 takes minutes of its own: run them in a call of their own with FILTER
# 'SphDamBreak/3D/0.00625/float/gpu'). SECONDS: time limit of the benchmark program. EXTRA:
# more sph_bench options, e.g. --sph_checkpoint_time=2 where t* = 6 cannot be reached in time
# (then say so beside the figures).
# Writes under $OUT: the checkpoint test's log, the benchmark JSON and text; prints a table.
set -u
B=${BUNDLE:-devbundle-ck}
OUT=${OUT:-/tmp/sph_bench_out}
FILTER=${1:-'SphDamBreak/(2D/.*|3D/(0.05|0.025|0.0125))/(float|double)/gpu'}
LIMIT=${2:-420}
EXTRA=${3:-}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,memory.total --format=csv,noheader
$B/run test_sph_checkpoint --gtest_filter='*gpu*' > "$OUT/test_sph_checkpoint.log" 2>&1
echo "test_sph_checkpoint gpu rc=$? $(grep -E '^\[  (PASSED|FAILED) |measured' "$OUT/test_sph_checkpoint.log" | tr '\n' ' ')"
timeout "$LIMIT" $B/run sph_bench --sph_cases="$B/data/cases" --sph_cache=/tmp/sph_bench_cache $EXTRA \
  --benchmark_filter="$FILTER" --benchmark_format=json --benchmark_out="$OUT/sph_bench.json" \
  > "$OUT/sph_bench.txt" 2> "$OUT/sph_bench.err"
echo "sph_bench rc=$? (124: stopped at the ${LIMIT} s limit; the finished cases are in the JSON only if it ended)"
grep "made" "$OUT/sph_bench.err"
python3 - "$OUT/sph_bench.json" <<'PY'
import json, sys
text = open(sys.argv[1]).read() if __import__("os").path.exists(sys.argv[1]) else ""
data = None
for tail in ("", "\n  ]\n}\n", "\n    }\n  ]\n}\n"):  # a run stopped by the limit leaves the JSON open
    try:
        data = json.loads(text + tail); break
    except Exception:
        pass
if data is None:
    print("no readable JSON"); sys.exit(0)
print("name fluid wall acoustic_steps fluid_steps/s pr_ms pr_ms/1e6 cand/s neigh/s neigh/particle bytes/particle")
for b in data["benchmarks"]:
    if "error_occurred" in b and b["error_occurred"]:
        print(b["name"], "ERROR", b.get("error_message")); continue
    print(b["name"], int(b["fluid_particles"]), int(b["wall_particles"]), int(b["acoustic_steps"]),
          "%.3e" % b["fluid_steps_per_s"], "%.4f" % b["pressure_relaxation_ms"], "%.4f" % b["pressure_relaxation_ms_per_1e6"],
          "%.3e" % b["candidate_pairs_per_s"], "%.3e" % b["neighbor_pairs_per_s"], "%.1f" % b["neighbors_per_fluid_particle"],
          "%.1f" % b["device_bytes_per_particle"])
PY
