#!/usr/bin/env bash
# scripts/fuzz_case.sh [SECONDS]   (default 60)
# Builds the libFuzzer target fuzz/case_fuzzer.cpp with clang (libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer) from the case-file reader (src/solver/case_file.cpp, toml++ header-only),
# then fuzzes for SECONDS over the seed corpus fuzz/corpus/cases (the case files, read only) and
# a working corpus in the build folder. Exits non-zero on a crash, a hang (> 10 s per input), a
# leak or a sanitizer report; the reproducer is written to the build folder.
# Environment: CLANGXX (default clang++-14, else clang++), UNISPH_FUZZ_DIR (default build/fuzz/case).
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${UNISPH_FUZZ_DIR:-$root/build/fuzz/case}
cxx=${CLANGXX:-$(command -v clang++-14 || command -v clang++)}
mkdir -p "$out/corpus"
(cd "$root" && "$cxx" -std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined \
   -fno-sanitize-recover=undefined -DUNISPH_HAS_CUDA=0 -Iinclude fuzz/case_fuzzer.cpp src/solver/case_file.cpp \
   -o "$out/case_fuzzer")
cd "$out"
exec ./case_fuzzer -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
  -print_final_stats=1 corpus "$root/fuzz/corpus/cases"
