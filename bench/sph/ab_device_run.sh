#!/usr/bin/env bash
# A/B of several sph_bench builds in one device call (docs/sph.md, "Neighbour records"), run
# from the repository root on the GPU machine with a bundle made by
#   strip -o /tmp/ab/sph_bench_base <main's build>/bench/sph/sph_bench
#   strip -o /tmp/ab/sph_bench_NAME <a variant's build>/bench/sph/sph_bench   (one per variant)
#   strip -o /tmp/ab/test_sph_methods <the variant's build>/tests/sph/test_sph_methods
#   /work/shared/tools/device-bundle /work/main/devbundle-gpu /tmp/ab/* -- cases
#   cp bench/sph/ab_device_run.sh /work/main/devbundle-gpu/
# and carried along (carry: devbundle-gpu). One step per call of this script:
#   ab_device_run.sh test                      the GPU tests of test_sph_methods
#   ab_device_run.sh ab TAG FILTER ROUNDS "BUILDS" [EXTRA]
#        ROUNDS rounds of the builds (e.g. "base rec"), interleaved, one process each; the
#        checkpoints are made by the first run and shared by all (the same file format);
#        EXTRA: more sph_bench options (e.g. --sph_checkpoint_time=1). A round starts only
#        while fewer than STOP_AFTER seconds (default 10^9) have passed since T0 (a date +%s;
#        default: this script's start).
#   ab_device_run.sh ncu FILTER "BUILDS"       Nsight Compute on one pressure and one density
#        relaxation pass of each build (launch 3 of each, after 20 acoustic steps)
#   ab_device_run.sh table                     the table of every ab run so far, and a tarball
# Writes under $OUT: tests.log, bench.err, ncu.txt, ab_table.txt, ab_json.tar.gz.
set -u
B=${BUNDLE:-devbundle-gpu}
OUT=${OUT:-/tmp/sph_ab_out}
RAW=/tmp/sph_ab_json
mkdir -p "$OUT" "$RAW"
export LD_LIBRARY_PATH="$PWD/$B/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
step=$1; shift
case "$step" in
test)
  nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,memory.total --format=csv,noheader
  "$B/bin/test_sph_methods" --gtest_filter='*gpu*' >> "$OUT/tests.log" 2>&1
  echo "test_sph_methods gpu rc=$? $(grep -E '^\[  (PASSED|FAILED) ' "$OUT/tests.log" | tail -1)"
  grep measured "$OUT/tests.log"
  ;;
ab)
  TAG=$1 FILTER=$2 ROUNDS=$3 BUILDS=$4 EXTRA=${5:-}
  for r in $(seq 1 "$ROUNDS"); do
    if [ $(( $(date +%s) - ${T0:-$(date +%s)} )) -ge "${STOP_AFTER:-1000000000}" ]; then echo "$TAG: round $r skipped (time)"; break; fi
    for b in $BUILDS; do
      "$B/bin/sph_bench_$b" --sph_cases="$B/data/cases" --sph_cache=/tmp/sph_bench_cache $EXTRA \
        --benchmark_filter="$FILTER" --benchmark_format=json --benchmark_out="$RAW/${TAG}_${b}_r$r.json" \
        > /dev/null 2>> "$OUT/bench.err"
      echo "$TAG $b round $r rc=$?"
    done
  done
  grep "made" "$OUT/bench.err" | sort -u
  ;;
ncu)
  FILTER=$1 BUILDS=$2
  NCU=$(command -v ncu || ls /usr/local/cuda/bin/ncu /opt/nvidia/nsight-compute/*/ncu 2>/dev/null | head -1)
  for b in $BUILDS; do
    echo "=== $b" >> "$OUT/ncu.txt"
    timeout "${NCU_LIMIT:-120}" "$NCU" --clock-control none --kernel-name-base demangled \
      -k 'regex:(PressureRelaxation|DensityRelaxation)<float, \(int\)3>::Kernel' --launch-skip 4 --launch-count 2 \
      --section SpeedOfLight --section LaunchStats --section Occupancy --section WarpStateStats \
      --section InstructionStats --section MemoryWorkloadAnalysis --section SchedulerStats \
      "$B/bin/sph_bench_$b" --sph_cases="$B/data/cases" --sph_cache=/tmp/sph_bench_cache --sph_steps=20 \
      --benchmark_filter="$FILTER" >> "$OUT/ncu.txt" 2>&1
    echo "ncu $b rc=$?"
  done
  grep -E "^=== |Relaxation<float, 3>|Duration|Registers Per|Achieved Occupancy|Theoretical Occupancy|Compute \(SM\) Throughput|Memory Throughput|L1/TEX Hit|L2 Hit|Issue Slots Busy|Executed Ipc Active|No Eligible|Warp Cycles Per Issued|Avg. Active Threads" "$OUT/ncu.txt" | head -80
  ;;
table)
  (cd "$RAW" && tar czf "$OUT/ab_json.tar.gz" ./*.json)
  python3 - "$RAW" > "$OUT/ab_table.txt" <<'PY'
import json, sys, os, glob
print("tag case build round fluid_steps/s pr_ms pr_ms/1e6 neigh/particle bytes/particle t*_restart")
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json")), key=os.path.getmtime):
    tag, build, rnd = os.path.basename(path)[:-5].rsplit("_", 2)
    try:
        data = json.load(open(path))
    except Exception as e:
        print(tag, build, rnd, "unreadable", e); continue
    for x in data["benchmarks"]:
        name = x["name"].split("/iterations")[0]
        if x.get("error_occurred"):
            print(tag, name, build, rnd, "ERROR", x.get("error_message")); continue
        print(tag, name, build, rnd, "%.4e" % x["fluid_steps_per_s"], "%.4f" % x["pressure_relaxation_ms"],
              "%.4f" % x["pressure_relaxation_ms_per_1e6"], "%.1f" % x["neighbors_per_fluid_particle"],
              "%.1f" % x["device_bytes_per_particle"], x.get("t_star_restart"))
PY
  cat "$OUT/ab_table.txt"
  ;;
esac
