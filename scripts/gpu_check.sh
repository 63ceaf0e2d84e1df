#!/usr/bin/env bash
# Runs every bundled test program's GPU instances (gtest filter */gpu.*) on a GPU machine and
# prints one line per program, then "N passed, N failed". Made for a bundle from
# scripts/gpu_bundle.sh:  BUNDLE/gpu_check.sh  (test data in BUNDLE/data).
set -u
here=$(cd "$(dirname "$0")" && pwd)
export UNISPH_TEST_DATA_DIR="$here/data"
passed=0
failed=0
for exe in "$here"/bin/test_*; do
  name=$(basename "$exe")
  out=$("$here/run" "$name" --gtest_filter='*/gpu.*' --gtest_brief=1 2>&1)
  rc=$?
  summary=$(printf '%s\n' "$out" | grep -E '^\[  (PASSED|FAILED)  \]' | tr '\n' ' ')
  if [ $rc -eq 0 ]; then
    passed=$((passed + 1))
    echo "ok     $name: $summary"
  else
    failed=$((failed + 1))
    echo "FAILED $name (exit $rc): $summary"
    printf '%s\n' "$out" | grep -E 'Failure|error|Expected|Which is|FAILED' | head -20
  fi
done
echo "$passed passed, $failed failed"
[ $failed -eq 0 ]
