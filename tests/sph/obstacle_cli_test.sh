#!/usr/bin/env bash
# An obstacle through the program: `unisph generate` makes the block's particles, a case names
# them with [[obstacle]], `unisph run` runs it and VTK's own reader checks the output
# (read_output_with_vtk.py --obstacle); broken [[obstacle]] entries each give one error line
# naming the case file, its line and the key, exit status != 0, and write nothing.
#   obstacle_cli_test.sh UNISPH CASES_DIR WORK_DIR READ_OUTPUT_WITH_VTK_PY
set -u
exe=$1; cases=$2; work=$3; reader=$4
rm -rf "$work"; mkdir -p "$work"
status=0
if ! "$exe" generate "$cases/obstacle_2d.poly" --dx 0.1 --iterations 100 --policy seq -o "$work/obstacle_2d.vtp" > "$work/generate.out" 2>&1; then
  echo "FAIL generate: $(cat "$work/generate.out")"; exit 1
fi
echo "ok   generate: $(head -1 "$work/generate.out")"
# The case of cases/ at dx = 0.1, its obstacle file next to it (a path relative to the case file).
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^output_interval = .*/output_interval = 0.5/' \
    "$cases/dambreak_obstacle_2d.toml" > "$work/obstacle.toml"
if ! /usr/bin/python3 "$reader" "$exe" "$work/obstacle.toml" "$work/out" --obstacle 3.366,0.0,3.766,0.6 --end-time 3; then
  echo "FAIL run with the obstacle"; status=1
fi
# Broken entries.
sed 's/^dx = 0.025 .*/dx = 0.05/' "$cases/dambreak_obstacle_2d.toml" > "$work/other_dx.toml"
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^file = .*/file = "absent.vtp"/' "$cases/dambreak_obstacle_2d.toml" > "$work/missing_file.toml"
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^translation = .*/translation = [5.2, 0.0]/' "$cases/dambreak_obstacle_2d.toml" > "$work/outside.toml"
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^translation = .*/rotation = 90.0/' "$cases/dambreak_obstacle_2d.toml" > "$work/unknown_key.toml"
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^translation = .*/translation = "right"/' "$cases/dambreak_obstacle_2d.toml" > "$work/wrong_type.toml"
cp "$cases/dambreak_2d.toml" "$work/not_particles.vtp"
sed -e 's/^dx = 0.025 .*/dx = 0.1/' -e 's/^file = .*/file = "not_particles.vtp"/' "$cases/dambreak_obstacle_2d.toml" > "$work/not_vtk.toml"
for case in "other_dx:obstacle.file:obstacle_2d.vtp: was generated with dx = 0.1; the case's dx is 0.05" \
            "missing_file:obstacle.file:absent.vtp: cannot open the file" \
            "outside:obstacle.file:lies outside the tank" \
            "unknown_key:obstacle.rotation:unknown key" \
            "wrong_type:obstacle.translation:must be an array" \
            "not_vtk:obstacle.file:not_particles.vtp: is not a VTK XML file"; do
  name=${case%%:*}; rest=${case#*:}; key=${rest%%:*}; expected=${rest#*:}
  "$exe" run "$work/$name.toml" --output "$work/out_$name" --policy seq > "$work/$name.out" 2> "$work/$name.err"
  rc=$?
  lines=$(wc -l < "$work/$name.err")
  if [ $rc -eq 0 ] || [ "$lines" -ne 1 ] || ! grep -q "$name.toml:[0-9]*: key '$key': .*$expected" "$work/$name.err" ||
     [ -e "$work/out_$name" ]; then
    echo "FAIL $name: rc $rc, $lines error lines: $(cat "$work/$name.err")"; status=1
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
done
exit $status
