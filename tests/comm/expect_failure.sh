#!/usr/bin/env bash
# expect_failure.sh SECONDS PATTERN COMMAND...: passes when COMMAND ends within SECONDS with a
# non-zero status and its output has a line matching PATTERN (grep -E) -- the failure of one
# rank stops every rank with one line naming the rank and the reason, and nothing hangs.
set -u
seconds=$1 pattern=$2
shift 2
out=$(timeout --kill-after=5 "$seconds" "$@" 2>&1)
status=$?
printf '%s\n' "$out"
if [ $status -eq 124 ] || [ $status -eq 137 ]; then
  echo "expect_failure: FAILED: still running after $seconds s (a hang)"
  exit 1
fi
if [ $status -eq 0 ]; then
  echo "expect_failure: FAILED: exit status 0, a failure was expected"
  exit 1
fi
lines=$(printf '%s\n' "$out" | grep -cE "$pattern")
if [ "$lines" -lt 1 ]; then
  echo "expect_failure: FAILED: no line matches '$pattern'"
  exit 1
fi
echo "expect_failure: passed (status $status, $lines matching line(s))"
