#!/usr/bin/env bash
# The main job: set up, build, and run `unisph demo` (real kernels on every policy this
# machine offers, checked against each other and timed). Extra arguments go to the demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset default >/dev/null
cmake --build --preset default --target unisph_app
build/default/apps/unisph/unisph info
build/default/apps/unisph/unisph demo "$@"
