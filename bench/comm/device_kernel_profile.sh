#!/usr/bin/env bash
# Where a rank of a multi-GPU run spends its device time, kernel by kernel, against one GPU on the
# same number of particles (docs/multi_gpu.md, session 28). Nsight Compute (`ncu`, on the GPU
# machines) times every kernel of `unisph` (gpu__time_duration; the kernels are serialised, so
# the times are each kernel's own, without overlap), one log per process:
#
#   BUNDLE=devbundle bench/comm/device_kernel_profile.sh OUT [RUNS...]   (on the GPU machine)
#
#   one      cases/dambreak_3d.toml at dx 0.00625 (4,096,000 fluid particles) on one GPU
#   weak_4   the tank and column four times as wide on four GPUs (4,096,000 per rank), NCCL
#   strong_4 the strong case on four GPUs, NCCL
#   share_4  one GPU on a quarter of the strong case (the tank and column 0.125 wide)
#
# END (default 0.02) is the simulated time. Then bench/comm/kernel_profile_summary.py OUT prints
# each kernel family's calls and time per run and rank.
set -euo pipefail
OUT=${1:?usage: BUNDLE=dir device_kernel_profile.sh OUT [RUNS...]}
shift
RUNS=("$@")
[ ${#RUNS[@]} -gt 0 ] || RUNS=(one weak_4 strong_4 share_4)
B=${BUNDLE:?set BUNDLE to the device bundle}
END=${END:-0.02}
DX=${DX:-0.00625}
LIMIT=${LIMIT:-400}
NCU=${NCU:-ncu}
HERE=$(cd "$(dirname "$0")/../.." && pwd)
W=$(mktemp -d)
mkdir -p "$OUT"
export NCCL_NVLS_ENABLE=0
command -v "$NCU" > /dev/null || { echo "device_kernel_profile: $NCU not found"; exit 2; }
# Our kernels and CUB's (NCCL's are left alone: profiling one would stall its peers).
NCU_ARGS=(--clock-control none --metrics gpu__time_duration.sum --kernel-name-base demangled
          --kernel-name 'regex:unisph|cub' --print-kernel-base demangled --csv --page raw)

widened() {  # name width case: the tank and column of the 3D dam break `width` wide
  local name=$1 width=$2 probe=$3
  sed -e "s/^tank = \[5.366, 2.0, 0.5\]/tank = [5.366, 2.0, $width]/" \
      -e "s/^column = \[2.0, 1.0, 0.5\]/column = [2.0, 1.0, $width]/" \
      -e "s/^position = \[\(.*\), 0.25\]/position = [\1, $probe]/" \
      -e "s/^name = \"dambreak_3d\"/name = \"dambreak_3d_$name\"/" "$HERE/cases/dambreak_3d.toml" > "$W/$name.toml"
  grep -q "tank = \[5.366, 2.0, $width\]" "$W/$name.toml" || { echo "case $name not made" >&2; exit 1; }
  echo "$W/$name.toml"
}

# One log per rank: the rank's number from Open MPI's environment.
{
  echo '#!/usr/bin/env bash'
  echo 'prefix=$1; shift'
  printf 'exec %q' "$NCU"; printf ' %q' "${NCU_ARGS[@]}"
  echo ' --log-file "$prefix.rank${OMPI_COMM_WORLD_RANK}.csv" "$@"'
} > "$W/ncu_rank.sh"
chmod +x "$W/ncu_rank.sh"

for name in "${RUNS[@]}"; do
  case $name in
    one) n=1; case_file=$HERE/cases/dambreak_3d.toml ;;
    weak_4) n=4; case_file=$(widened weak_4 2.0 1.0) ;;
    strong_4) n=4; case_file=$HERE/cases/dambreak_3d.toml ;;
    share_4) n=1; case_file=$(widened share_4 0.125 0.0625) ;;
    *) echo "unknown run $name"; continue ;;
  esac
  cmd=("$B/run" unisph run "$case_file" --policy device --precision float --dx "$DX" --end-time "$END"
       --output "$W/$name" --quiet --no-snapshots)
  start=$(date +%s)
  if [ "$n" -gt 1 ]; then
    UNISPH_TRANSPORT=nccl timeout "$LIMIT" mpirun --allow-run-as-root --bind-to none -x NCCL_NVLS_ENABLE -x UNISPH_TRANSPORT \
      -np "$n" "$W/ncu_rank.sh" "$OUT/$name" "${cmd[@]}" > "$OUT/$name.out" 2>&1 || echo "$name FAILED: $(tail -2 "$OUT/$name.out")"
  else
    timeout "$LIMIT" "$NCU" "${NCU_ARGS[@]}" --log-file "$OUT/$name.rank0.csv" "${cmd[@]}" > "$OUT/$name.out" 2>&1 ||
      echo "$name FAILED: $(tail -2 "$OUT/$name.out")"
  fi
  cp "$W/$name/run.log" "$OUT/$name.log" 2>/dev/null || true
  echo "$name: $(( $(date +%s) - start )) s"
done
rm -rf "$W"
