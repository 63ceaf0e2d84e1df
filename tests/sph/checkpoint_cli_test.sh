#!/usr/bin/env bash
# `unisph run --checkpoint-every` and `--restart` through the program (seq, the 2D dam break
# to t = 1):   checkpoint_cli_test.sh UNISPH CASES_DIR WORK_DIR
#  * a run that writes checkpoints takes the same steps as one that does not (same files);
#  * a restart into a new folder ends with the same snapshot, byte for byte;
#  * a restart into the folder of a run that crashed after its checkpoint (simulated: later
#    files left behind) rewrites its observer series and collection to the same bytes;
#  * a truncated file, another precision, a file that is no checkpoint and another case are
#    refused with one line naming the file, exit status 1.
set -u
exe=$1; cases=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
status=0
fail() { echo "FAIL $*"; status=1; }
ok() { echo "ok   $*"; }
run() { "$exe" run "$@" --policy seq --quiet; }

run "$cases/dambreak_2d.toml" --end-time 1 --output "$work/straight" || fail "straight run"
run "$cases/dambreak_2d.toml" --end-time 1 --checkpoint-every 0.45 --output "$work/with_checkpoints" || fail "run with checkpoints"
ck="$work/with_checkpoints/checkpoint.bin"
[ -s "$ck" ] && [ ! -e "$ck.tmp" ] || fail "no checkpoint written (or its .tmp left)"
for f in observers.csv Water_000002.vtp dambreak_2d.pvd; do
  cmp -s "$work/straight/$f" "$work/with_checkpoints/$f" && ok "checkpoints change nothing: $f" || fail "$f differs with checkpoints"
done

run --restart "$ck" --output "$work/restarted" || fail "restart"
cmp -s "$work/straight/Water_000002.vtp" "$work/restarted/Water_000002.vtp" && ok "restart in a new folder: last snapshot bit for bit" ||
  fail "restarted snapshot differs"
grep -q "^restarted from: $ck" "$work/restarted/run.log" || fail "run.log does not name the checkpoint"

# A crash after the checkpoint: the folder holds the checkpoint and whatever came after it.
cp -r "$work/with_checkpoints" "$work/crashed"
echo "9.99,garbage written after the checkpoint" >> "$work/crashed/observers.csv"
run "$cases/dambreak_2d.toml" --restart "$work/crashed/checkpoint.bin" --output "$work/crashed" || fail "restart in place"
for f in observers.csv Water_000002.vtp dambreak_2d.pvd; do
  cmp -s "$work/straight/$f" "$work/crashed/$f" && ok "restart in place: $f as the straight run's" || fail "restart in place: $f differs"
done

head -c 5000 "$ck" > "$work/truncated.bin"
refuse() {  # name, expected text, arguments...
  local name=$1 expected=$2; shift 2
  "$exe" run "$@" --policy seq --quiet --output "$work/out_$name" > /dev/null 2> "$work/$name.err"
  local rc=$? lines; lines=$(wc -l < "$work/$name.err")
  if [ $rc -ne 1 ] || [ "$lines" -ne 1 ] || ! grep -qF -- "$expected" "$work/$name.err" || [ -e "$work/out_$name" ]; then
    fail "$name: rc $rc, $lines lines: $(cat "$work/$name.err")"
  else
    ok "$name: $(cat "$work/$name.err")"
  fi
}
refuse truncated "checkpoint $work/truncated.bin: is truncated" --restart "$work/truncated.bin"
refuse precision "checkpoint $ck: holds a double run; --precision float cannot continue it" --restart "$ck" --precision float
refuse not_a_checkpoint "checkpoint $cases/dambreak_2d.toml: is not a unisph checkpoint" --restart "$cases/dambreak_2d.toml"
refuse other_case "checkpoint $ck: was written for another case than $cases/hydrostatic_2d.toml: geometry.tank" \
  "$cases/hydrostatic_2d.toml" --restart "$ck"
exit $status
