#!/usr/bin/env bash
# scripts/sph_device_runs.sh BUNDLE OUT
# The SPH runs behind docs/validation.md, on the GPU: the policy-agreement test, the validation
# cases on the device (their observer files go to OUT for the plots and figures), and the
# throughput table (2D at H/40..H/320, 3D at dx 0.05..0.00625, float and double, short runs
# from t = 0; the figure is run.log's fluid-particle acoustic steps per second).
# BUNDLE is a /work/shared/tools/device-bundle folder holding unisph, test_sph_methods and cases/.
set -uo pipefail
B=$1; OUT=$2; D=$B/data/cases; W=$(mktemp -d)
nvidia-smi --query-gpu=name,memory.total --format=csv,noheader
"$B/run" test_sph_methods --gtest_filter='*gpu*' 2>&1 | grep -E "measured|FAILED|Failure|actual" | sort -u
run() {  # name case args...
  local name=$1 case=$2; shift 2
  "$B/run" unisph run "$D/$case" --policy device --output "$W/$name" --quiet "$@" || echo "$name FAILED"
  awk -v n="$name" -F': ' '/^precision/{p=$2} /^dx/{dx=$2} /^fluid particles/{f=$2} /^wall particles/{w=$2}
    /^acoustic steps/{s=$2} /^wall time \(time loop/{t=$2} /^fluid-particle acoustic steps per second:/{r=$2}
    END{printf "%-16s dx %-8s %-6s fluid %8d wall %8d acoustic %6d loop %s rate %s\n", n, dx, p, f, w, s, t, r}' "$W/$name/run.log"
}
run dambreak_2d dambreak_2d.toml;            cp "$W/dambreak_2d/observers.csv" "$OUT/dambreak_2d.csv"
run dambreak_2d_f dambreak_2d.toml --precision float; cp "$W/dambreak_2d_f/observers.csv" "$OUT/dambreak_2d_float.csv"
run column40 column_collapse_2d.toml;        cp "$W/column40/observers.csv" "$OUT/column_collapse_2d.csv"
run column80 column_collapse_2d.toml --dx 0.0125; cp "$W/column80/observers.csv" "$OUT/column_collapse_2d_dx80.csv"
run hydrostatic hydrostatic_2d.toml;         cp "$W/hydrostatic/observers.csv" "$OUT/hydrostatic_2d.csv"
# First and last snapshot: sph_run_metrics.py moved OUT/hydrostatic_first.vtp OUT/hydrostatic_last.vtp 0.025
cp "$W/hydrostatic/Water_000000.vtp" "$OUT/hydrostatic_first.vtp"; cp "$(ls "$W"/hydrostatic/Water_*.vtp | tail -1)" "$OUT/hydrostatic_last.vtp"
run dambreak_3d_025 dambreak_3d.toml --dx 0.025 --precision float; cp "$W/dambreak_3d_025/observers.csv" "$OUT/dambreak_3d_dx0.025.csv"
run dambreak_3d_0125 dambreak_3d.toml --dx 0.0125 --precision float --end-time 6; cp "$W/dambreak_3d_0125/observers.csv" "$OUT/dambreak_3d_dx0.0125.csv"
# The resolution study of docs/validation.md: the dam break to t* = 6 at H/80..H/320 (crossing and
# window mean: sph_run_metrics.py crossing FILE), the column at L/dx = 160, 3D dx 0.0125 in double.
for n in 80 160 320; do
  run "dambreak_2d_H$n" dambreak_2d.toml --dx $(awk "BEGIN{print 1/$n}") --end-time 6; cp "$W/dambreak_2d_H$n/observers.csv" "$OUT/dambreak_2d_H$n.csv"
done
run dambreak_2d_H320_f dambreak_2d.toml --dx 0.003125 --end-time 6 --precision float; cp "$W/dambreak_2d_H320_f/observers.csv" "$OUT/dambreak_2d_H320_float.csv"
run column160 column_collapse_2d.toml --dx 0.00625; cp "$W/column160/observers.csv" "$OUT/column_collapse_2d_dx160.csv"
run dambreak_3d_0125_d dambreak_3d.toml --dx 0.0125 --end-time 6; cp "$W/dambreak_3d_0125_d/observers.csv" "$OUT/dambreak_3d_dx0.0125_double.csv"
for p in float double; do
  for n in 40 80 160 320; do run "2d_H$n" dambreak_2d.toml --dx $(awk "BEGIN{print 1/$n}") --precision $p --end-time 0.5; done
  for dx in 0.05 0.025 0.0125 0.00625; do run "3d_$dx" dambreak_3d.toml --dx $dx --precision $p --end-time 0.1; done
done
rm -rf "$W"
