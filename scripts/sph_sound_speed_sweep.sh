#!/usr/bin/env bash
# scripts/sph_sound_speed_sweep.sh UNISPH POLICY OUT [C0S] [RESOLUTIONS]
# The 2D dam break (cases/dambreak_2d.toml, the summed density) at several sound speeds and
# resolutions, to t*sqrt(g/H) = 6: the wall probes' window means, noise and lowest values, one line
# per run (docs/validation.md, "The sound speed"). The observer files go to OUT/s_C0_HN.csv.
#   UNISPH       the command that runs the program: build/default/apps/unisph/unisph, or on a GPU
#                machine "BUNDLE/run unisph" (a device-bundle folder with cases/ and scripts/ as data)
#   POLICY       seq, par or device
#   C0S          sound speeds in units of sqrt(g H) (default "10 14 20 30"; the case's is 20)
#   RESOLUTIONS  H/dx values (default "40"; the GPU runs of session 26: "40 80 160 320")
# Run from the repository root, or give CASES and SCRIPTS (the folders of the case and of
# sph_run_metrics.py) in the environment.
set -uo pipefail
UNISPH=$1; POLICY=$2; OUT=$3; C0S=${4:-10 14 20 30}; RESOLUTIONS=${5:-40}
CASES=${CASES:-cases}; SCRIPTS=${SCRIPTS:-scripts}
PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3
W=$(mktemp -d); mkdir -p "$OUT"
for c in $C0S; do
  # The case's line is "sound_speed = 20.0   # c0 = 10 U"; only its value changes.
  sed "s/^sound_speed = [0-9.]*/sound_speed = $c/" "$CASES/dambreak_2d.toml" > "$W/c$c.toml"
  grep -q "^sound_speed = $c" "$W/c$c.toml" || { echo "no sound_speed line in $CASES/dambreak_2d.toml" >&2; exit 1; }
  for n in $RESOLUTIONS; do
    name="s_${c}_H$n"
    $UNISPH run "$W/c$c.toml" --policy "$POLICY" --dx "$(awk "BEGIN{print 1/$n}")" --end-time 6 --no-snapshots --quiet \
      --output "$W/$name" > /dev/null 2>&1 || { echo "$name FAILED: $(tail -1 "$W/$name/run.log")"; continue; }
    cp "$W/$name/observers.csv" "$OUT/$name.csv"
    "$PY" "$SCRIPTS/sph_run_metrics.py" summary "$OUT/$name.csv" | awk -v n="c0 $c H/$n" '
      NR > 1 { m[$1] = $3; z[$1] = $4; d[$1] = $5; x[$1] = $2 }
      END { printf "%-14s 0.2H crossing %.3f; means 0.01/0.1/0.2/0.267H %.3f %.3f %.3f %.3f (0.2H wide %.3f); noise %.3f %.3f %.3f %.3f; lowest at 0.2H %.2f\n",
            n, x["0.2H"], m["0.01H"], m["0.1H"], m["0.2H"], m["0.267H"], m["0.2H_wide"], z["0.01H"], z["0.1H"], z["0.2H"], z["0.267H"], d["0.2H"] }'
  done
done
rm -rf "$W"
