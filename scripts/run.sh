#!/usr/bin/env bash
# The main job: set up, build, and run the 2D dam break (cases/dambreak_2d.toml) on the best
# policy this machine offers (the GPU where there is one, else all CPU threads). The result
# goes to build/dambreak_2d/ (open dambreak_2d.pvd in ParaView). Extra arguments go to
# `unisph run` (e.g. --policy seq, --end-time 5, --dx 0.0125).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset default >/dev/null
cmake --build --preset default --target unisph_app
build/default/apps/unisph/unisph info
build/default/apps/unisph/unisph run cases/dambreak_2d.toml --output build/dambreak_2d "$@"
