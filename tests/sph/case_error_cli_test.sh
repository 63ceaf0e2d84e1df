#!/usr/bin/env bash
# `unisph run` on a broken case file: exit status != 0, one error line naming file, line and key,
# and no output folder written; a run that blows up names step, variable and particle.   case_error_cli_test.sh UNISPH CASES_DIR WORK_DIR
set -u
exe=$1; cases=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
sed 's/^dx = 0.025 .*/dx = -0.025/' "$cases/dambreak_2d.toml" > "$work/negative_dx.toml"
sed 's/^column = \[2.0, 1.0\]/column = [6.0, 1.0]/' "$cases/dambreak_2d.toml" > "$work/big_column.toml"
sed 's/^gravity = 1.0/gravity = "down"/' "$cases/dambreak_2d.toml" > "$work/wrong_type.toml"
sed 's/^sound_speed = 20.0.*/sound_speed = 20.0\nspeed_of_sound = 20.0/' "$cases/dambreak_2d.toml" > "$work/unknown_key.toml"
sed '/^density = 1.0/d' "$cases/dambreak_2d.toml" > "$work/missing.toml"
sed 's/^continuity_dissipation = true.*/continuity_dissipation = true\nkernel_gradient_correction = 1/' "$cases/dambreak_2d.toml" > "$work/not_boolean.toml"
sed 's/^continuity_dissipation = true.*/continuity_dissipation = true\nparticle_shifting = 2.0/' "$cases/dambreak_2d.toml" > "$work/shifting_too_large.toml"
sed 's/^continuity_dissipation = true.*/continuity_dissipation = true\nparticle_shifting = -0.4/' "$cases/dambreak_2d.toml" > "$work/shifting_negative.toml"
# h / dx out of its range; the short form's 4 wall layers too few for h = 1.9 dx; a flume's
# bodies' default 4 layers too few for h = 1.9 dx (the first wall body is named).
sed 's/^dx = 0.025 .*/dx = 0.025\nsmoothing_length_ratio = 2.5/' "$cases/dambreak_2d.toml" > "$work/ratio_too_large.toml"
sed 's/^dx = 0.025 .*/dx = 0.025\nsmoothing_length_ratio = 1.9/' "$cases/dambreak_2d.toml" > "$work/ratio_short_form.toml"
sed 's/^smoothing_length_ratio = 1.6/smoothing_length_ratio = 1.9/' "$cases/piston_flume_2d.toml" > "$work/too_few_layers.toml"
status=0
for case in ratio_too_large:geometry.smoothing_length_ratio ratio_short_form:geometry.smoothing_length_ratio \
            too_few_layers:body.layers negative_dx:geometry.dx big_column:geometry.column wrong_type:physics.gravity unknown_key:fluid.speed_of_sound missing:fluid.density \
            not_boolean:fluid.kernel_gradient_correction shifting_too_large:fluid.particle_shifting \
            shifting_negative:fluid.particle_shifting; do
  name=${case%%:*}; key=${case#*:}
  "$exe" run "$work/$name.toml" --output "$work/out_$name" --policy seq > "$work/$name.out" 2> "$work/$name.err"
  rc=$?
  lines=$(wc -l < "$work/$name.err")
  if [ $rc -eq 0 ] || [ "$lines" -ne 1 ] || ! grep -q "$name.toml:[0-9]*: key '$key'" "$work/$name.err" || [ -e "$work/out_$name" ]; then
    echo "FAIL $name: rc $rc, $lines error lines: $(cat "$work/$name.err")"; status=1
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
done
# A run that blows up (c0 far too small: the water falls through the floor) stops with a
# diagnostic naming the step, the variable and the particle, exit status 2, snapshots kept.
sed 's/^sound_speed = 20.0.*/sound_speed = 0.3/' "$cases/dambreak_2d.toml" > "$work/blow_up.toml"
"$exe" run "$work/blow_up.toml" --policy seq --end-time 3 --output "$work/out_blow_up" --quiet 2> "$work/blow_up.err"
rc=$?
if [ $rc -ne 2 ] || ! grep -q "step [0-9]* (t = .*): variable 'Position (outside the domain)' of fluid particle id [0-9]*" "$work/blow_up.err" ||
   [ ! -s "$work/out_blow_up/Water_000000.vtp" ] || ! grep -q "^FAILED: " "$work/out_blow_up/run.log"; then
  echo "FAIL blow_up: rc $rc: $(cat "$work/blow_up.err")"; status=1
else
  echo "ok   blow_up: $(cat "$work/blow_up.err")"
fi
# Absurd parameters: each run stops with status 2 and one diagnostic, the first snapshot kept.
#   gravity 1e308: the values overflow within the first advection step -> the first non-finite
#     variable (in the order a step computes them) and the particle;
#   sound speed 1e200: the acoustic step would be 1e-199 of the advection step -> named, not a hang;
#   viscosity 1e300: the viscous advection step would be 1e-304 -> named, not a hang.
sed 's/^gravity = 1.0/gravity = 1.0e308/' "$cases/dambreak_2d.toml" > "$work/overflow.toml"
sed 's/^sound_speed = 20.0.*/sound_speed = 1.0e200/' "$cases/dambreak_2d.toml" > "$work/sound_speed.toml"
sed 's/^sound_speed = 20.0.*/sound_speed = 20.0\nviscosity = 1.0e300/' "$cases/dambreak_2d.toml" > "$work/viscosity.toml"
for case in "overflow:variable 'Density (not finite)' of fluid particle id [0-9]* (index [0-9]*), at" \
            "sound_speed:would take .* acoustic steps .*fluid.sound_speed 1e+200" \
            "viscosity:the advection step .* is below 1e-9 of the end time .*fluid.viscosity 1e+300"; do
  name=${case%%:*}; expected=${case#*:}
  timeout 120 "$exe" run "$work/$name.toml" --policy seq --end-time 1 --output "$work/out_$name" --quiet 2> "$work/$name.err"
  rc=$?
  if [ $rc -ne 2 ] || [ "$(wc -l < "$work/$name.err")" -ne 1 ] || ! grep -q "step 0 (t = 0): .*$expected" "$work/$name.err" ||
     [ ! -s "$work/out_$name/Water_000000.vtp" ] || ! grep -q "^FAILED: " "$work/out_$name/run.log"; then
    echo "FAIL $name: rc $rc: $(cat "$work/$name.err")"; status=1
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
done
exit $status
