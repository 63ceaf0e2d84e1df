#!/usr/bin/env bash
# scripts/fuzz_stl.sh [SECONDS]   (default 60)
# Builds the libFuzzer target fuzz/stl_fuzzer.cpp with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) from the geometry sources it needs, then fuzzes for SECONDS over
# the seed corpus fuzz/corpus/stl (read only) and a working corpus in the build folder (where
# new inputs go). Exits non-zero on a crash, a hang (> 10 s per input), a leak or a sanitizer
# report; the reproducer is written to the build folder (crash-*, timeout-*, leak-*).
# Environment: CLANGXX (default clang++-14, else clang++), UNISPH_FUZZ_DIR (default build/fuzz/<target>),
# UNISPH_FUZZ_TARGET=polygon fuzzes the polygon reader instead (fuzz/polygon_fuzzer.cpp,
# corpus fuzz/corpus/polygons).
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
target=${UNISPH_FUZZ_TARGET:-stl}
case $target in
  stl) fuzzer=stl_fuzzer; seeds=fuzz/corpus/stl; dict=(-dict="$root/fuzz/stl.dict") ;;
  polygon) fuzzer=polygon_fuzzer; seeds=fuzz/corpus/polygons; dict=() ;;
  *) echo "fuzz_stl.sh: UNISPH_FUZZ_TARGET is '$target': use stl or polygon" >&2; exit 2 ;;
esac
out=${UNISPH_FUZZ_DIR:-$root/build/fuzz/$target}
cxx=${CLANGXX:-$(command -v clang++-14 || command -v clang++)}
mkdir -p "$out/corpus"

sources=(fuzz/$fuzzer.cpp src/geometry/stl_reader.cpp src/geometry/mesh_repair.cpp src/geometry/bvh.cpp
         src/geometry/triangle_mesh_search.cpp src/geometry/polygon_reader.cpp src/geometry/polygon_search.cpp
         src/memory/variable_base.cpp src/exec/policy.cpp src/cuda/runtime.cpp)
(cd "$root" && "$cxx" -std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
   -fno-sanitize-recover=undefined -DUNISPH_HAS_CUDA=0 -Iinclude "${sources[@]}" -ltbb -o "$out/$fuzzer")

cd "$out"
exec "./$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  "${dict[@]}" -print_final_stats=1 corpus "$root/$seeds"
