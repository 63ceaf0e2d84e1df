// The 2D solver in float and double, compiled once (by nvcc where CUDA is on).
#include "unisph/solver/weakly_compressible_solver_impl.hpp"

namespace unisph::sph {
template class WeaklyCompressibleSolver<float, 2>;
template class WeaklyCompressibleSolver<double, 2>;
}  // namespace unisph::sph
