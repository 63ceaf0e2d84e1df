#!/usr/bin/env bash
# scripts/gpu_bundle.sh BUILD_DIR DEST
# Collects the test programs of a CUDA build (stripped, to stay under the device machine's
# 64 MiB carry limit), the libraries they need, tests/data and gpu_check.sh into DEST, for the
# GPU machine:  DEST/gpu_check.sh
set -euo pipefail
build=$1
dest=$2
root=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
find "$build/tests" -maxdepth 3 -type f -name 'test_*' -perm -u+x -exec cp {} "$tmp/" \;
strip "$tmp"/test_*
bundle=${UNISPH_DEVICE_BUNDLE:-$root/../shared/tools/device-bundle}
"$bundle" "$dest" "$tmp"/test_* -- "$root/tests/data/." >/dev/null
cp "$root/scripts/gpu_check.sh" "$dest/"
rm -rf "$tmp"
du -sh "$dest"
