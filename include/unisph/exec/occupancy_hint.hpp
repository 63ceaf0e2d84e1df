#pragma once
// An occupancy hint a kernel may give the GPU backend:
//
//   struct Kernel { static constexpr int min_blocks_per_multiprocessor = 5; ... };
//
// asks the compiler (CUDA __launch_bounds__) to fit that many blocks of the backend's block size
// on one multiprocessor, i.e. to cap the registers per thread (blocks of 256 threads: 5 blocks,
// at most 51 registers; 4 blocks, 64; 3 blocks, 85). Without it, nvcc chooses the register count
// itself, and for the neighbour loops of SPH its choice moves with small changes of the code: the
// 3D float pressure relaxation took 48 registers (5 blocks) in one version of the neighbour walk
// and 61 (4 blocks, 15 % slower on an H100) in another with the same loop body. Host backends
// ignore the hint. 0 (the default) is no hint.

namespace unisph {

template <class F>
constexpr int min_blocks_per_multiprocessor() {
  if constexpr (requires { F::min_blocks_per_multiprocessor; })
    return F::min_blocks_per_multiprocessor;
  else
    return 0;  // no hint: the compiler chooses
}

}  // namespace unisph
