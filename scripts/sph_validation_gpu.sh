#!/usr/bin/env bash
# scripts/sph_validation_gpu.sh BUNDLE OUT [PART]
# Issue 23's dam-break bands at the resolutions the 2-core CPU cannot afford, on one GPU
# (docs/validation.md): the observer files go to OUT under the names scripts/sph_bands.py reads,
# and the band table is printed at the end. BUNDLE: a /work/shared/tools/device-bundle folder
# holding unisph and test_sph_methods, with cases/ and scripts/ as data.
#   PART 2d   the policy test on the GPU; the 2D dam break at H/40, 80, 160, 320 (double, to
#             t* = 6) and, for the before/after table, H/40 and H/320 with the summed density
#             (the cases' method before issue 23)
#   PART 3d   the 3D dam break (Lobovsky's tank) at dx = 0.0125 (double) and 0.00625 (float)
#   (default: both)
set -uo pipefail
B=$1; OUT=$2; PART=${3:-all}; D=$B/data/cases; W=$(mktemp -d)
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,memory.total --format=csv,noheader
run() {  # name case args...: observers to OUT/name.csv, the log's figures on one line
  local name=$1 case=$2; shift 2
  "$B/run" unisph run "$case" --policy device --output "$W/$name" --quiet "$@" || echo "$name FAILED: $(tail -1 "$W/$name/run.log")"
  cp "$W/$name/observers.csv" "$OUT/$name.csv"
  awk -v n="$name" -F': ' '/^precision/{p=$2} /^fluid particles/{f=$2} /^acoustic steps/{s=$2}
    /^wall time \(time loop/{t=$2} /^fluid-particle acoustic steps per second:/{r=$2}
    END{printf "%-26s %-6s fluid %8d acoustic %6d loop %s rate %s\n", n, p, f, s, t, r}' "$W/$name/run.log"
}
if [ "$PART" != 3d ]; then
  "$B/run" test_sph_methods --gtest_filter='*gpu*' 2>&1 | grep -E "measured|FAILED|Failure|actual" | sort -u
  for n in 40 80 160 320; do
    run "dambreak_2d_H$n" "$D/dambreak_2d.toml" --dx "$(awk "BEGIN{print 1/$n}")" --end-time 6
  done
  sed 's/^density_method = "continuity".*/density_method = "summation"/; s/^density_diffusion = 0.1.*//;
       s/^continuity_dissipation = false.*/continuity_dissipation = true/' \
    "$D/dambreak_2d.toml" > "$W/dambreak_2d_summation.toml"
  mkdir -p "$OUT/summation"
  for n in 40 320; do
    run "summation/dambreak_2d_H$n" "$W/dambreak_2d_summation.toml" --dx "$(awk "BEGIN{print 1/$n}")" --end-time 6
  done
fi
if [ "$PART" != 2d ]; then
  run dambreak_3d_dx0.0125 "$D/dambreak_3d.toml" --dx 0.0125 --end-time 6
  run dambreak_3d_dx0.00625 "$D/dambreak_3d.toml" --dx 0.00625 --precision float --end-time 6
fi
python3 "$B/data/scripts/sph_bands.py" "$OUT"
[ -d "$OUT/summation" ] && { echo "--- the summed density (fluid.density_method = \"summation\"), for comparison:"; python3 "$B/data/scripts/sph_bands.py" "$OUT/summation"; }
rm -rf "$W"
