#!/usr/bin/env bash
# scripts/fuzz_vtp.sh [SECONDS]   (default 60)
# Builds the libFuzzer target fuzz/vtp_fuzzer.cpp with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) from the .vtp reader (io/vtk_xml_reader.hpp, header-only),
# then fuzzes for SECONDS over the seed corpus fuzz/corpus/vtp (particle files of unisph generate and run, read only) and
# a working corpus in the build folder. Exits non-zero on a crash, a hang (> 10 s per input), a
# leak or a sanitizer report; the reproducer is written to the build folder.
# Environment: CLANGXX (default clang++-14, else clang++), UNISPH_FUZZ_DIR (default build/fuzz/vtp).
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${UNISPH_FUZZ_DIR:-$root/build/fuzz/vtp}
cxx=${CLANGXX:-$(command -v clang++-14 || command -v clang++)}
mkdir -p "$out/corpus"
(cd "$root" && "$cxx" -std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
   -fno-sanitize-recover=undefined -DUNISPH_HAS_CUDA=0 -Iinclude fuzz/vtp_fuzzer.cpp \
   -o "$out/vtp_fuzzer")
cd "$out"
exec ./vtp_fuzzer -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -print_final_stats=1 corpus "$root/fuzz/corpus/vtp"
