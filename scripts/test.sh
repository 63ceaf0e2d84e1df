#!/usr/bin/env bash
# Set up, build and run every test this machine can run:
#   1. the default preset (CUDA backend compiled where nvcc is found; the tests' gpu instances
#      where a GPU is visible)
#   2. the asan preset (clang's AddressSanitizer + UndefinedBehaviorSanitizer, CPU, single precision)
#   3. install, and build + run a downstream project against the installed tree (find_package)
#   4. the libFuzzer targets, briefly (UNISPH_FUZZ_SECONDS each, default 30, two at a time: the whole run inside an hour on the 2-core CI machine)
# Prints the time of each stage.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
stage_start=$(date +%s)
stage() {
  local now
  now=$(date +%s)
  echo "=== [$(date +%T)] previous stage took $((now - stage_start)) s; now: $*"
  stage_start=$now
}

stage "set-up"
scripts/setup.sh

stage "module graph: no include points up (scripts/check_includes.sh)"
scripts/check_includes.sh

stage "configure + build (default preset)"
# Without a GPU the tests' gpu instances could only skip: the tests are compiled as host C++ (seq
# and par) against the CUDA-built library, in about half nvcc's time (UNISPH_GPU_TESTS,
# tests/CMakeLists.txt). The library, the program, the benchmarks and the examples are compiled
# by nvcc where it is found, either way.
gpu_tests=OFF
if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >/dev/null 2>&1; then gpu_tests=ON; fi
echo "GPU visible: UNISPH_GPU_TESTS=$gpu_tests"
cmake --preset default -DUNISPH_GPU_TESTS=$gpu_tests
cmake --build --preset default -j "$jobs"

stage "tests (default preset)"
ctest --preset default -j "$jobs" -LE validation

# The SPH validation runs against experiments and peers (issue 23's bands, docs/validation.md)
# and the Taylor-Green decay (issue 21, about 20 s on `par`) decide the outcome. Only the SPH runs: the particle-relaxation validation (test_relaxation_validation,
# also labelled validation) takes hours on two cores and is run by hand and on the GPU
# (docs/particle_generation.md); the finer dam breaks run on a GPU (scripts/sph_validation_gpu.sh).
stage "SPH validation against experiments and peers (gating)"
ctest --preset default -j "$jobs" -L validation -LE open -R '^(test_sph_validation|test_sph_periodic\.TaylorGreenDecayRate\.par$)' --output-on-failure
# The bands the method does not meet yet (label `open`): run and printed, not gating.
stage "SPH validation: the bands not met yet (reported, not gating)"
ctest --preset default -j "$jobs" -L open -R '^test_sph_validation' --output-on-failure || echo "validation: the open bands are outside their bounds, as docs/validation.md reports"

stage "configure + build (asan preset)"
cmake --preset asan
cmake --build --preset asan -j "$jobs"

stage "tests (asan preset)"
# The entries labelled not_under_sanitizers (the `seq` twins of long `par` entries, and long runs
# of kernels that shorter tests run) and the longest cases of some tests (SANITIZER_SKIP) are left
# out; tests/CMakeLists.txt says which and why (docs/architecture.md, "Continuous integration").
ctest --preset asan -j "$jobs" -LE 'validation|not_under_sanitizers'

stage "install + downstream find_package(unisph) project"
rm -rf build/default/install build/consumer
cmake --install build/default --prefix build/default/install >/dev/null
cmake -S tests/consumer -B build/consumer -G Ninja -DCMAKE_PREFIX_PATH="$PWD/build/default/install"
cmake --build build/consumer
build/consumer/consumer

# The four libFuzzer targets two at a time: each builds with one clang process and fuzzes on one
# thread, so a pair fills the two cores (about 60 s a pair on them; one after another, 230 s).
fuzz_pair() {  # "name command..." twice; prints each log, fails where either failed
  local logs=() pids=() names=() failed=0 k
  for k in 1 2; do
    local name=$1 cmd=$2
    shift 2
    logs+=("$(mktemp)")
    names+=("$name")
    bash -c "$cmd" > "${logs[-1]}" 2>&1 &
    pids+=($!)
  done
  for k in 0 1; do
    if wait "${pids[$k]}"; then echo "--- ${names[$k]}: passed"; else echo "--- ${names[$k]}: FAILED"; failed=1; fi
    tail -n 25 "${logs[$k]}"
    rm -f "${logs[$k]}"
  done
  return $failed
}
seconds=${UNISPH_FUZZ_SECONDS:-30}
stage "fuzz the STL and polygon readers for $seconds s each, side by side"
fuzz_pair "STL reader" "scripts/fuzz_stl.sh $seconds" \
          "polygon reader" "UNISPH_FUZZ_TARGET=polygon scripts/fuzz_stl.sh $seconds"

stage "fuzz the case-file and .vtp particle-file readers for $seconds s each, side by side"
fuzz_pair "case-file reader" "scripts/fuzz_case.sh $seconds" \
          ".vtp reader" "scripts/fuzz_vtp.sh $seconds"

stage "done"
