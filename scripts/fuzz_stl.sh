#!/usr/bin/env bash
# scripts/fuzz_stl.sh [SECONDS]   (default 60)
# Builds the libFuzzer target fuzz/stl_fuzzer.cpp with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) from the geometry sources it needs, then fuzzes for SECONDS over
# the seed corpus fuzz/corpus/stl (read only) and a working corpus in the build folder (where
# new inputs go). Exits non-zero on a crash, a hang (> 10 s per input), a leak or a sanitizer
# report; the reproducer is written to the build folder (crash-*, timeout-*, leak-*).
# Environment: CLANGXX (default clang++-14, else clang++), UNISPH_FUZZ_DIR (default build/fuzz).
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${UNISPH_FUZZ_DIR:-$root/build/fuzz}
cxx=${CLANGXX:-$(command -v clang++-14 || command -v clang++)}
mkdir -p "$out/corpus"

sources=(fuzz/stl_fuzzer.cpp src/geometry/stl_reader.cpp src/geometry/mesh_repair.cpp src/geometry/bvh.cpp
         src/geometry/triangle_mesh_search.cpp src/memory/variable_base.cpp src/exec/policy.cpp src/cuda/runtime.cpp)
(cd "$root" && "$cxx" -std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
   -fno-sanitize-recover=undefined -DUNISPH_HAS_CUDA=0 -Iinclude "${sources[@]}" -ltbb -o "$out/stl_fuzzer")

cd "$out"
exec ./stl_fuzzer -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -dict="$root/fuzz/stl.dict" -print_final_stats=1 corpus "$root/fuzz/corpus/stl"
