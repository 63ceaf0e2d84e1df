#pragma once
// Frees the grow-only scratch storage of the device algorithms (runtime.hpp, scratch()) after
// waiting for the device; the next algorithm allocates what it needs. For set-up work much
// larger than a run's (a case's particles made on a lattice over the whole domain), so that the
// run does not keep that set-up's scratch for its lifetime. Does nothing in a build without CUDA.
namespace unisph::cuda {

void release_scratch();

}  // namespace unisph::cuda
