// The 3D solver in float and double, compiled once (by nvcc where CUDA is on).
#include "unisph/solver/weakly_compressible_solver_impl.hpp"

namespace unisph::sph {
template class WeaklyCompressibleSolver<float, 3>;
template class WeaklyCompressibleSolver<double, 3>;
}  // namespace unisph::sph
