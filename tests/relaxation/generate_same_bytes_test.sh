#!/usr/bin/env bash
# `unisph generate` on POLICY writes the same bytes as on seq (particles and residual history):
# the relaxation gives the same bits on every policy (docs/particle_generation.md).
#   generate_same_bytes_test.sh UNISPH GEOMETRY DX ITERATIONS POLICY OUTDIR
# Exit 77 (skipped) where POLICY is device and this machine has no usable GPU.
set -euo pipefail
unisph=$1 geometry=$2 dx=$3 iterations=$4 policy=$5 out=$6
mkdir -p "$out"
"$unisph" generate "$geometry" --dx "$dx" --iterations "$iterations" --policy seq -o "$out/seq.vtp" > "$out/seq.log"
if ! "$unisph" generate "$geometry" --dx "$dx" --iterations "$iterations" --policy "$policy" -o "$out/$policy.vtp" \
    > "$out/$policy.log" 2>&1; then
  if [ "$policy" = device ] && grep -qi "cuda\|gpu\|device" "$out/$policy.log"; then
    echo "skipped: $(tail -1 "$out/$policy.log")"
    exit 77
  fi
  cat "$out/$policy.log"
  exit 1
fi
cmp "$out/seq.vtp" "$out/$policy.vtp"
cmp "$out/seq_residual.csv" "$out/${policy}_residual.csv"
echo "$policy: the same particles and history as seq, byte for byte ($(grep -c . "$out/seq_residual.csv") history rows)"
