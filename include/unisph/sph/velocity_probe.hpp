#pragma once
// Velocity probes: the fluid's velocity at fixed points, kernel-weighted and normalised
// (Shepard), from the fluid particles within the kernel's support (issue 22, "Measurements";
// docs/motion.md, "Measurements and wave absorption"):
//
//   v(x) = sum_j v_j W(|x - x_j|) V_j / sum_j W(|x - x_j|) V_j,     V_j = m_j / rho_j,
//
// over the fluid particles closer than the cutoff (a direct search through the fluid's cell
// list, PointNeighbors). Where none is, the probe is dry: the velocity is 0 and `wet` is false.
//
// Accuracy. The normalisation makes a uniform field exact: the sum is taken of v_j - v_ref, v_ref
// the velocity of the first particle the search finds, and v_ref is added back, so a uniform
// field gives its value bit for bit. A linear field v = a + B x gives a + B x_bar, x_bar the
// kernel-weighted mean position of the particles around x: exact where the particles lie
// symmetrically about x (inside a lattice: at a particle, a cell centre, an edge's midpoint);
// elsewhere inside the square lattice at h = 1.3 dx the first moment |x_bar - x| is at most
// 0.0068 dx in 2D (a sum over the lattice), so the error is at most 0.0068 dx |B|
// (test_sph_measurements measures it). A smooth field
// adds its curvature's O(h^2) smoothing. Within 2h of the free surface or a wall the particles
// lie on one side of x, x_bar moves into the fluid by up to about h, and the probe reads the
// velocity there: put probes at least 2h = 2.6 dx inside the water for point values.
//
// All probes run in one launch (one thread per probe); measure() copies their sums to the host.
//
//   VelocityProbes<T, 2> probes(fluid, fluid_cells, kernel, {{"u1", {{1.0, 0.5}}}});
//   std::vector<VelocityReading<T, 2>> v = probes.measure(policy);   // v[p].velocity, v[p].wet
#include <cmath>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/point_neighbors.hpp"

namespace unisph::sph {

// One probe: its name (CSV columns velocity_<name>_x, _y(, _z)) and its point.
template <class T, int D>
struct VelocityProbePoint {
  std::string name;
  Vec<T, D> position;
};

template <class T, int D>
struct VelocityReading {
  Vec<T, D> velocity;  // the Shepard average; 0 when dry
  T kernel_sum;        // sum_j W V_j: about 1 inside the fluid, 1/2 at a flat surface, 0 dry
  bool wet;            // some fluid particle lies within the support
};

// What the kernel leaves per probe: the reference velocity, the weighted sum of the velocities
// relative to it and the sum of the weights.
template <class T, int D>
struct VelocityProbeSums {
  Vec<T, D> reference;
  Vec<T, D> weighted;
  T weight;
};

template <class T, int D>
class VelocityProbes : public UpdateDynamics<VelocityProbes<T, D>> {
 public:
  // `fluid_cells`: the fluid's cell list (inner.cell_list()), with a cutoff at least the kernel's.
  // Throws unisph::Error (one line) for an empty, duplicate or unprintable name or a point that is
  // not finite.
  VelocityProbes(FluidVariables<T, D>& fluid, CellLinkedList<T, D>& fluid_cells, WendlandC2Kernel<T, D> kernel,
                 std::vector<VelocityProbePoint<T, D>> probes)
      : fluid_(fluid), cells_(fluid_cells), kernel_(kernel), probes_(std::move(probes)),
        points_("VelocityProbes.Points"), sums_("VelocityProbes.Sums") {
    if (!(fluid_cells.grid().cutoff >= kernel.cutoff()))
      throw Error("velocity probes: the cell list's cutoff " + std::to_string(fluid_cells.grid().cutoff) +
                  " is below the kernel's " + std::to_string(kernel.cutoff()));
    std::vector<Vec<T, D>> points;
    for (std::size_t p = 0; p < probes_.size(); ++p) {
      check_probe(p);
      points.push_back(probes_[p].position);
    }
    points_.assign(std::span<const Vec<T, D>>(points.data(), points.size()));
    sums_.resize(points_.size());
  }

  struct Kernel {
    PointNeighbors<T, D> fluid;
    View<const Vec<T, D>> points;
    View<const Vec<T, D>> velocity;
    View<const T> mass, density;
    View<VelocityProbeSums<T, D>> sums;
    WendlandC2Kernel<T, D> kernel;
    UNISPH_HOST_DEVICE void update(Index p, Real) const {
      VelocityProbeSums<T, D> s{};
      bool first = true;
      fluid.for_each(points[p], [&](Index j, T r) {
        if (first) {
          s.reference = velocity[j];
          first = false;
        }
        const T w = kernel.value(r) * (mass[j] / density[j]);
        s.weighted += (velocity[j] - s.reference) * w;
        s.weight += w;
      });
      sums[p] = s;
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {PointNeighbors<T, D>::make(c, cells_), c.read(points_),      c.read(fluid_.velocity),
            c.read(fluid_.mass),                   c.read(fluid_.density), c.write(sums_),
            kernel_};
  }
  // One item per probe.
  Index size() const { return points_.size(); }

  template <ExecutionPolicy P>
  std::vector<VelocityReading<T, D>> measure(P policy) {
    return readings(sums(policy));
  }
  // The two halves of measure(), for probes spread over ranks (each probe's sums taken by the
  // rank that owns its point, then combined): the sums of every probe (one launch, copied to
  // the host), and the readings from such sums.
  template <ExecutionPolicy P>
  std::vector<VelocityProbeSums<T, D>> sums(P policy) {
    if (probes_.empty()) return {};
    this->exec(policy);
    return sums_.to_vector();
  }
  static std::vector<VelocityReading<T, D>> readings(std::span<const VelocityProbeSums<T, D>> sums) {
    std::vector<VelocityReading<T, D>> out;
    for (const VelocityProbeSums<T, D>& s : sums) {
      if (s.weight > T(0))
        out.push_back({s.reference + s.weighted / s.weight, s.weight, true});
      else
        out.push_back({Vec<T, D>{}, s.weight, false});
    }
    return out;
  }

  const std::vector<VelocityProbePoint<T, D>>& probes() const { return probes_; }
  // The observer CSV's columns, D per probe in the order of measure()'s readings:
  // velocity_<name>_x, velocity_<name>_y (, velocity_<name>_z).
  std::vector<std::string> column_names() const {
    static constexpr const char* axis[3] = {"_x", "_y", "_z"};
    std::vector<std::string> names;
    for (const VelocityProbePoint<T, D>& p : probes_)
      for (int a = 0; a < D; ++a) names.push_back("velocity_" + p.name + axis[a]);
    return names;
  }

 private:
  void check_probe(std::size_t index) const {
    const VelocityProbePoint<T, D>& probe = probes_[index];
    const std::string who = "velocity probe " + std::to_string(index) + " '" + probe.name + "'";
    if (probe.name.empty()) throw Error("velocity probe " + std::to_string(index) + ": the name is empty");
    for (char ch : probe.name) {
      const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                      ch == '-' || ch == '.';
      if (!ok) throw Error(who + ": the name may hold letters, digits, '_', '-' and '.' only (it names CSV columns)");
    }
    for (std::size_t other = 0; other < index; ++other)
      if (probes_[other].name == probe.name) throw Error(who + ": the name is taken by probe " + std::to_string(other));
    for (int a = 0; a < D; ++a)
      if (!std::isfinite(probe.position[a])) throw Error(who + ": the position must be finite");
  }

  FluidVariables<T, D>& fluid_;
  CellLinkedList<T, D>& cells_;
  WendlandC2Kernel<T, D> kernel_;
  std::vector<VelocityProbePoint<T, D>> probes_;
  DiscreteVariable<Vec<T, D>> points_;
  DiscreteVariable<VelocityProbeSums<T, D>> sums_;
};

}  // namespace unisph::sph
