#!/usr/bin/env bash
# Scaling of `unisph run` over the GPUs of one node (docs/multi_gpu.md, "Scaling"): the 3D dam
# break in single precision, one MPI rank per GPU, from t = 0 to END (default 0.05).
#
#   BUNDLE=devbundle bench/comm/device_scaling.sh OUT [GPUS...]      (on the GPU machine)
#
#   strong   cases/dambreak_3d.toml at dx 0.00625 (4,096,000 fluid particles) on each GPU count,
#            NCCL; host-staged beside it on the largest count
#   weak     the same column and tank widened with the GPU count (4,096,000 fluid particles per
#            GPU: the flow of each slice is that of one GPU's case), NCCL
#   share    one GPU with one N-th of the strong case (the tank and column narrowed to 0.5 / N):
#            the rate one GPU reaches on each GPU's share, which bounds the strong speed-up on N
#            (N times the share's rate over the whole case's)
#
# OVERLAP_AB=1 runs the strong and weak cases on the largest count once more with
# UNISPH_HALO_OVERLAP=0 (the ghosts' refreshes not overlapped with the interior particles' work;
# names ending in _whole), to measure what the overlap gives.
#
# For each run one line (and OUT/scaling.csv): GPUs, transport, fluid particles, acoustic steps,
# the time loop and its snapshots, fluid-particle acoustic steps per second without them, and
# the slowest rank's time in acoustic steps (ghost refreshes among them), in the ends of advection
# steps, and exchanging with plans per acoustic step (run.log's rank lines, time loop only; one
# GPU: its acoustic steps and step ends), and the least and most a rank waited for the others in
# the largest speed's reductions.
set -euo pipefail
OUT=${1:?usage: BUNDLE=dir device_scaling.sh OUT [GPUS...]}
shift
GPUS=("$@")
[ ${#GPUS[@]} -gt 0 ] || GPUS=(1 2 4)
B=${BUNDLE:?set BUNDLE to the device bundle}
END=${END:-0.05}
DX=${DX:-0.00625}
LIMIT=${LIMIT:-150}  # seconds per run (a hung run is stopped and named FAILED)
HERE=$(cd "$(dirname "$0")/../.." && pwd)
W=$(mktemp -d)
mkdir -p "$OUT"
export NCCL_NVLS_ENABLE=0
echo "gpus,mode,transport,fluid,acoustic_steps,loop_s,snapshot_s,steps_per_s,acoustic_s_max,refresh_s_max,step_end_s_max,exchange_plan_ms_per_step_max,speed_wait_s_min,speed_wait_s_max" > "$OUT/scaling.csv"

run() {  # name gpus transport case
  local name=$1 n=$2 transport=$3 case=$4
  local dir="$W/$name"
  local cmd=("$B/run" unisph run "$case" --policy device --precision float --dx "$DX" --end-time "$END" --output "$dir" --quiet)
  if [ "$n" -gt 1 ]; then
    local overlap=()
    [[ "$name" == *_whole ]] && overlap=(-x UNISPH_HALO_OVERLAP=0)
    UNISPH_TRANSPORT=$transport timeout "$LIMIT" mpirun --allow-run-as-root --bind-to none -x NCCL_NVLS_ENABLE -x UNISPH_TRANSPORT \
      "${overlap[@]}" -np "$n" "${cmd[@]}" > "$dir.out" 2>&1 || echo "$name FAILED: $(tail -1 "$dir.out")"
  else
    timeout "$LIMIT" "${cmd[@]}" > "$dir.out" 2>&1 || echo "$name FAILED: $(tail -1 "$dir.out")"
  fi
  cp "$dir/run.log" "$OUT/$name.log" 2>/dev/null || { echo "$name: no run.log"; cat "$dir.out"; return; }
  awk -v name="$name" -v n="$n" -v t="$transport" -F': ' '
    function field(line, label,   at) { at = index(line, label); return at ? substr(line, at + length(label)) + 0 : 0 }
    /^fluid particles/{f=$2} /^acoustic steps/{s=$2} /^wall time \(time loop/{l=$2+0}
    /^wall time writing snapshots/{w=$2+0} /^fluid-particle acoustic steps per second, snapshots excluded/{rate=$2}
    /^time loop: acoustic steps/{ am = field($0, "acoustic steps "); em = field($0, "advection-step ends ") }
    /^rank [0-9]+:/{ a = field($0, "acoustic steps "); e = field($0, "advection-step ends ");
        x = field($0, "exchanging and plans "); r = field($0, "ghost refreshes in them ");
        v = field($0, "reductions "); if (vn == "" || v < vn) vn = v; if (v > vx) vx = v;
        if (a > am) am = a; if (e > em) em = e; if (x > xm) xm = x; if (r > rm) rm = r }
    END{ printf "%-13s %d GPU %-11s fluid %9d acoustic %4d loop %6.2f s (snapshots %5.2f s) %.3e steps/s | slowest rank: acoustic %.3f s (refreshes %.3f s), step ends %.3f s, exchange+plans %.2f ms/step, waiting in speed reductions %.3f to %.3f s\n", name, n, t, f, s, l, w, rate, am, rm, em, xm, vn, vx
         printf "%d,%s,%s,%d,%d,%.3f,%.3f,%.4e,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n", n, (name ~ /^weak/ ? "weak" : name ~ /^share/ ? "share" : "strong") (name ~ /_whole$/ ? "_whole" : ""), t, f, s, l, w, rate, am, rm, em, xm, vn, vx >> OUT_CSV }' \
    OUT_CSV="$OUT/scaling.csv" "$dir/run.log"
}

largest=${GPUS[${#GPUS[@]}-1]}
for n in "${GPUS[@]}"; do
  run "strong_$n" "$n" nccl "$HERE/cases/dambreak_3d.toml"
done
[ "$largest" -gt 1 ] && run "strong_${largest}_host" "$largest" host_staged "$HERE/cases/dambreak_3d.toml"
[ "$largest" -gt 1 ] && [ "${OVERLAP_AB:-0}" = 1 ] && run "strong_${largest}_whole" "$largest" nccl "$HERE/cases/dambreak_3d.toml"
for n in "${GPUS[@]}"; do
  [ "$n" -gt 1 ] || continue
  width=$(awk -v n="$n" 'BEGIN{print 0.5 * n}')
  sed -e "s/^tank = \[5.366, 2.0, 0.5\]/tank = [5.366, 2.0, $width]/" \
      -e "s/^column = \[2.0, 1.0, 0.5\]/column = [2.0, 1.0, $width]/" \
      -e "s/^name = \"dambreak_3d\"/name = \"dambreak_3d_weak_$n\"/" "$HERE/cases/dambreak_3d.toml" > "$W/weak_$n.toml"
  grep -q "tank = \[5.366, 2.0, $width\]" "$W/weak_$n.toml" || { echo "weak case $n not made"; continue; }
  run "weak_$n" "$n" nccl "$W/weak_$n.toml"
  [ "${OVERLAP_AB:-0}" = 1 ] && [ "$n" = "$largest" ] && run "weak_${n}_whole" "$n" nccl "$W/weak_$n.toml"
done
for n in "${GPUS[@]}"; do
  [ "$n" -gt 1 ] || continue
  width=$(awk -v n="$n" 'BEGIN{print 0.5 / n}')
  half=$(awk -v n="$n" 'BEGIN{print 0.25 / n}')  # the probes at mid-width
  sed -e "s/^position = \[\(.*\), 0.25\]/position = [\1, $half]/" -e "s/^tank = \[5.366, 2.0, 0.5\]/tank = [5.366, 2.0, $width]/" \
      -e "s/^column = \[2.0, 1.0, 0.5\]/column = [2.0, 1.0, $width]/" \
      -e "s/^name = \"dambreak_3d\"/name = \"dambreak_3d_share_$n\"/" "$HERE/cases/dambreak_3d.toml" > "$W/share_$n.toml"
  grep -q "tank = \[5.366, 2.0, $width\]" "$W/share_$n.toml" || { echo "share case $n not made"; continue; }
  run "share_$n" 1 - "$W/share_$n.toml"
done
rm -rf "$W"
