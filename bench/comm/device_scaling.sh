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
#
# For each run one line (and OUT/scaling.csv): GPUs, transport, fluid particles, acoustic steps,
# the time loop without snapshots, fluid-particle acoustic steps per second, and per rank the
# time building plans and exchanging, per acoustic step (run.log's lines).
set -euo pipefail
OUT=${1:?usage: BUNDLE=dir device_scaling.sh OUT [GPUS...]}
shift
GPUS=("$@")
[ ${#GPUS[@]} -gt 0 ] || GPUS=(1 2 4)
B=${BUNDLE:?set BUNDLE to the device bundle}
END=${END:-0.05}
DX=${DX:-0.00625}
HERE=$(cd "$(dirname "$0")/../.." && pwd)
W=$(mktemp -d)
mkdir -p "$OUT"
export NCCL_NVLS_ENABLE=0
echo "gpus,mode,transport,fluid,acoustic_steps,loop_s,snapshot_s,steps_per_s,plan_ms_per_step_max,exchange_ms_per_step_max" > "$OUT/scaling.csv"

run() {  # name gpus transport case
  local name=$1 n=$2 transport=$3 case=$4
  local dir="$W/$name"
  local cmd=("$B/run" unisph run "$case" --policy device --precision float --dx "$DX" --end-time "$END" --output "$dir" --quiet)
  if [ "$n" -gt 1 ]; then
    UNISPH_TRANSPORT=$transport mpirun --allow-run-as-root --bind-to none -x NCCL_NVLS_ENABLE -x UNISPH_TRANSPORT \
      -np "$n" "${cmd[@]}" > "$dir.out" 2>&1 || echo "$name FAILED: $(tail -1 "$dir.out")"
  else
    "${cmd[@]}" > "$dir.out" 2>&1 || echo "$name FAILED: $(tail -1 "$dir.out")"
  fi
  cp "$dir/run.log" "$OUT/$name.log" 2>/dev/null || { echo "$name: no run.log"; cat "$dir.out"; return; }
  awk -v name="$name" -v n="$n" -v t="$transport" -F': ' '
    /^fluid particles/{f=$2} /^acoustic steps/{s=$2} /^wall time \(time loop/{l=$2+0}
    /^wall time writing snapshots/{w=$2+0} /^fluid-particle acoustic steps per second, snapshots excluded/{r=$2}
    /^rank [0-9]+:/{ if (match($0, /; [0-9.e+-]+ s building plans, [0-9.e+-]+ s in/)) {
        split(substr($0, RSTART + 2, RLENGTH), a, " "); p = a[1]; x = a[5];
        if (p > pm) pm = p; if (x > xm) xm = x } }
    END{ if (s > 0) { pm = 1e3 * pm / s; xm = 1e3 * xm / s }
         printf "%-12s %d GPU %-11s fluid %9d acoustic %5d loop %7.2f s (snapshots %5.2f s) %.3e steps/s  plans %.2f ms, exchange %.2f ms per step (slowest rank)\n", name, n, t, f, s, l, w, r, pm, xm
         printf "%d,%s,%s,%d,%d,%.3f,%.3f,%.4e,%.3f,%.3f\n", n, (name ~ /^weak/ ? "weak" : "strong"), t, f, s, l, w, r, pm, xm >> OUT_CSV }' \
    OUT_CSV="$OUT/scaling.csv" "$dir/run.log"
}

largest=${GPUS[${#GPUS[@]}-1]}
for n in "${GPUS[@]}"; do
  run "strong_$n" "$n" nccl "$HERE/cases/dambreak_3d.toml"
done
[ "$largest" -gt 1 ] && run "strong_${largest}_host" "$largest" host_staged "$HERE/cases/dambreak_3d.toml"
for n in "${GPUS[@]}"; do
  [ "$n" -gt 1 ] || continue
  width=$(awk -v n="$n" 'BEGIN{print 0.5 * n}')
  sed -e "s/^tank = \[5.366, 2.0, 0.5\]/tank = [5.366, 2.0, $width]/" \
      -e "s/^column = \[2.0, 1.0, 0.5\]/column = [2.0, 1.0, $width]/" \
      -e "s/^name = \"dambreak_3d\"/name = \"dambreak_3d_weak_$n\"/" "$HERE/cases/dambreak_3d.toml" > "$W/weak_$n.toml"
  grep -q "tank = \[5.366, 2.0, $width\]" "$W/weak_$n.toml" || { echo "weak case $n not made"; continue; }
  run "weak_$n" "$n" nccl "$W/weak_$n.toml"
done
rm -rf "$W"
