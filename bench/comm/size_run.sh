#!/usr/bin/env bash
# The size run of docs/multi_gpu.md ("10^9 particles"): the 3D dam break at dx = 0.001
# (1,000,000,000 fluid and 115,823,936 wall particles) in single precision on N GPUs of one
# node, one MPI rank per GPU, NCCL, 98 acoustic steps (t = 0 to 0.0032), no snapshots (each
# would be about 30 GB), with cutoff-wide cells (time.cells_per_cutoff = 1: every rank's cell
# table spans the whole domain, and half-cutoff cells would take 8 times its 2.3 GiB).
#
#   BUNDLE=devbundle bench/comm/size_run.sh OUT [GPUS] [DX] [END]      (on the GPU machine)
#
# Writes OUT/run.log (the set-up's wall time, the rate, device memory per particle and per
# rank, with unisph's largest allocations) and OUT/observers.csv, and prints the lines the
# docs quote.
set -euo pipefail
OUT=${1:?usage: BUNDLE=dir size_run.sh OUT [GPUS] [DX] [END]}
N=${2:-4}
DX=${3:-0.001}
END=${4:-0.0032}
B=${BUNDLE:?set BUNDLE to the device bundle}
HERE=$(cd "$(dirname "$0")/../.." && pwd)
W=$(mktemp -d)
mkdir -p "$OUT"
export NCCL_NVLS_ENABLE=0
sed -e 's/^\[time\]/[time]\ncells_per_cutoff = 1/' -e 's/^name = "dambreak_3d"/name = "dambreak_3d_size"/' \
  "$HERE/cases/dambreak_3d.toml" > "$W/size.toml"
grep -q "^cells_per_cutoff = 1" "$W/size.toml" || { echo "size case not made"; exit 1; }
# unisph's switches, where set, reach every rank (UNISPH_OWNED_VIEWS=0: the run without owned views).
forward=()
for v in UNISPH_OWNED_VIEWS UNISPH_HALO_OVERLAP UNISPH_TRANSPORT UNISPH_DECOMPOSITION; do
  [ -n "${!v:-}" ] && forward+=(-x "$v")
done
timeout "${LIMIT:-540}" mpirun --allow-run-as-root --bind-to none -x NCCL_NVLS_ENABLE "${forward[@]}" -np "$N" \
  "$B/run" unisph run "$W/size.toml" --policy device --precision float --dx "$DX" --end-time "$END" \
  --no-snapshots --quiet --output "$W/run"
cp "$W/run/run.log" "$W/run/observers.csv" "$OUT/"
grep -E "^(fluid|wall) particles|^device memory|^acoustic steps|^wall time setting up|^wall time \(time loop|per second, snapshots excluded" "$OUT/run.log"
rm -rf "$W"
