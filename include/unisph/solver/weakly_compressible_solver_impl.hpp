#pragma once
// Definitions of WeaklyCompressibleSolver, included only by the library's instantiation
// files (src/solver/), which nvcc compiles where CUDA is on.
#include <algorithm>
#include <chrono>
#include <optional>
#include <span>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>

#include "unisph/comm/interior_split.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/io/checkpoint_file.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/pair_counts.hpp"
#include "unisph/neighbor/periodic_images.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/sph/damping_zone.hpp"
#include "unisph/sph/density_relaxation.hpp"
#include "unisph/sph/density_summation.hpp"
#include "unisph/sph/image_records.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/sph/fused_updates.hpp"
#include "unisph/sph/observers.hpp"
#include "unisph/solver/body_particles.hpp"
#include "unisph/solver/obstacle_particles.hpp"
#include "unisph/sph/pressure_relaxation.hpp"
#include "unisph/sph/wall_pressure_average.hpp"
#include "unisph/solver/rank_share.hpp"
#include "unisph/solver/solver_checkpoint.hpp"
#include "unisph/sph/moving_walls.hpp"
#include "unisph/sph/particle_shifting.hpp"
#include "unisph/sph/wall_load.hpp"
#include "unisph/sph/velocity_probe.hpp"
#include "unisph/sph/wave_gauge.hpp"
#include "unisph/sph/prior_acceleration.hpp"
#include "unisph/motion/motion_table.hpp"
#include "unisph/solver/tank_particles.hpp"
#include "unisph/sph/time_step.hpp"
#include "unisph/sph/velocity_damping.hpp"
#include "unisph/sph/wall_free_box.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

namespace unisph::sph {


template <class T, int D>
struct WeaklyCompressibleSolver<T, D>::State {
  using Vector = Vec<T, D>;

  // The general form's [domain]; the short form's tank with its walls.
  static Box<T, D> domain_of(const CaseDescription& c) {
    Box<T, D> box{};
    for (int a = 0; a < D; ++a) {
      if (c.general()) {
        box.lower[a] = T(c.domain.lower[std::size_t(a)]);
        box.upper[a] = T(c.domain.upper[std::size_t(a)]);
      } else {
        box.lower[a] = T(-wall_layers * c.dx);
        box.upper[a] = T(c.tank[a] + wall_layers * c.dx);
      }
    }
    return box;
  }
  // physics.gravity as a vector; a description without one (a C++ program's short form) has
  // |g| along -y.
  static Vector gravity_of(const CaseDescription& c) {
    Vector g{};
    if (int(c.gravity_vector.size()) == D)
      for (int a = 0; a < D; ++a) g[a] = T(c.gravity_vector[std::size_t(a)]);
    else
      g[1] = T(-c.gravity);
    return g;
  }
  static T volume_of(double dx) {
    double v = 1;
    for (int a = 0; a < D; ++a) v *= dx;
    return T(v);
  }
  static SearchMethod search_method_of(const CaseDescription& c) {
    if (c.neighbor_search == "stored") return SearchMethod::stored;
    if (c.neighbor_search == "direct") return SearchMethod::direct;
    return SearchMethod::automatic;
  }
  // time.cells_per_cutoff; automatic: half-cutoff cells on the GPU, cutoff cells on the CPU
  // (where the 5^D stencil's extra rows cost more than the candidates it saves).
  static T cell_size_of(const CaseDescription& c, PolicyKind kind, T cutoff) {
    int split = c.cells_per_cutoff;
    if (split == 0) split = kind == PolicyKind::device ? 2 : 1;
    return split == 2 ? cutoff / T(2) : cutoff;
  }
  static const CaseDescription& checked(const CaseDescription& c) {
    if (c.dimension != D)
      throw Error("case '" + c.name + "' is " + std::to_string(c.dimension) + "D; this solver is " + std::to_string(D) + "D");
    if (c.general()) {
      if (int(c.domain.lower.size()) != D || int(c.domain.upper.size()) != D)
        throw Error("case '" + c.name + "': the domain needs " + std::to_string(D) + " lower and upper bounds");
    } else if (int(c.tank.size()) != D || int(c.column.size()) != D) {
      throw Error("case '" + c.name + "': tank and column need " + std::to_string(D) + " sizes");
    }
    if (!c.domain.periodic.empty()) {
      if (!c.general()) throw Error("case '" + c.name + "': periodic axes need the general form ([domain], [[body]])");
      const double cutoff = double(WendlandC2Kernel<T, D>::from_spacing(T(c.dx), T(c.smoothing_length_ratio)).cutoff());
      for (int a : c.domain.periodic) {
        if (a < 0 || a >= D) throw Error("case '" + c.name + "': periodic axis " + std::to_string(a) + " in a " + std::to_string(D) + "D case");
        const double length = c.domain.upper[std::size_t(a)] - c.domain.lower[std::size_t(a)];
        if (!(length >= 2 * cutoff))
          throw CaseFileError(periodic_where(c) + "the domain is " + format(length) + " wide along periodic axis " +
                              axis_name(a) + ", narrower than two cutoffs (2 x 2 h = " + format(2 * cutoff) +
                              "): ghost images would be wider than the domain");
        // The lattice must close on itself across the faces: a length of whole spacings.
        const double cells = length / c.dx;
        if (!(std::abs(cells - std::round(cells)) <= 1e-6 * cells))
          throw CaseFileError(periodic_where(c) + "the domain's length along periodic axis " + axis_name(a) + " (" +
                              format(length) + ") is not a whole number of particle spacings dx = " + format(c.dx) +
                              " (" + format(cells) + "): the lattice would not join across the faces");
      }
    }
    return c;
  }
  static const char* axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : "z"; }
  static std::string format(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  static std::string periodic_where(const CaseDescription& c) {
    return c.source + ":" + std::to_string(c.domain.periodic_line) + ": key 'domain.periodic': ";
  }
  // Ghost images of a body along the case's periodic axes; none (no object, no launch) without.
  static std::unique_ptr<PeriodicImages<T, D>> images_of(const CaseDescription& c, Body<T, D>& body, const Box<T, D>& domain,
                                                         T cutoff) {
    if (c.domain.periodic.empty()) return nullptr;
    std::array<bool, D> periodic{};
    for (int a : c.domain.periodic) periodic[std::size_t(a)] = true;
    return std::make_unique<PeriodicImages<T, D>>(body.particles(), body.positions(), domain, periodic, cutoff);
  }
  // A wall particle within the cutoff of a periodic face whose normal points along that axis
  // belongs to a wall across the axis (a side wall at the face, a plate that ends there): the
  // fluid would cross the face into it. A wall along a periodic axis (a channel's plate) runs
  // through both faces, its normals across the axis: it is given images like the fluid.
  static void check_walls_along_periodic_axes(const CaseDescription& c, const TankParticles<T, D>& p, const Box<T, D>& domain,
                                              const std::vector<WallBodyCount>& groups, double cutoff) {
    if (c.domain.periodic.empty()) return;
    std::size_t group = 0, end = groups.empty() ? 0 : std::size_t(groups[0].count);
    for (std::size_t k = 0; k < p.wall.size(); ++k) {
      while (k >= end && group + 1 < groups.size()) end += std::size_t(groups[++group].count);
      for (int a : c.domain.periodic) {
        const double x = double(p.wall[k][a]);
        const bool near_lower = x - double(domain.lower[a]) < cutoff, near_upper = double(domain.upper[a]) - x < cutoff;
        if (!near_lower && !near_upper) continue;
        if (std::abs(double(p.wall_normal[k][a])) <= 0.01) continue;
        std::ostringstream s;
        s << "wall body '" << (groups.empty() ? std::string("wall") : groups[group].name) << "' lies across periodic axis "
          << axis_name(a) << ": its particle at (";
        for (int b = 0; b < D; ++b) s << (b ? ", " : "") << double(p.wall[k][b]);
        s << "), within the cutoff of the face " << axis_name(a) << " = " << double(near_lower ? domain.lower[a] : domain.upper[a])
          << ", faces along " << axis_name(a) << " (normal " << axis_name(a) << " component " << double(p.wall_normal[k][a])
          << "); a wall along a periodic axis must run through both faces (make its shape reach beyond the domain)";
        throw CaseFileError(periodic_where(c) + s.str());
      }
    }
    // A wall must continue through the faces: each lattice particle of a wall in the first layer
    // at a periodic face has a wall particle beside it across the face (one dx on, wrapped by
    // L). A plate that ends at the face (its normals there turned towards the fluid) fails.
    // Particles off the lattice (x = (i + 1/2) dx: [[obstacle]] files) are not checked.
    using Key = std::array<long long, D>;
    const auto key_of = [&](const Vec<T, D>& x, Key& k) {
      for (int a = 0; a < D; ++a) {
        const double q = double(x[a]) / c.dx - 0.5;
        k[std::size_t(a)] = std::llround(q);
        if (std::abs(q - double(k[std::size_t(a)])) > 1e-3) return false;
      }
      return true;
    };
    std::set<Key> lattice;
    Key k{};
    for (const Vec<T, D>& x : p.wall)
      if (key_of(x, k)) lattice.insert(k);
    group = 0, end = groups.empty() ? 0 : std::size_t(groups[0].count);
    for (std::size_t w = 0; w < p.wall.size(); ++w) {
      while (w >= end && group + 1 < groups.size()) end += std::size_t(groups[++group].count);
      if (!key_of(p.wall[w], k)) continue;
      for (int a : c.domain.periodic) {
        const double x = double(p.wall[w][a]);
        const long long cells = std::llround((double(domain.upper[a]) - double(domain.lower[a])) / c.dx);
        long long step = 0;
        if (x - double(domain.lower[a]) < c.dx) step = cells - 1;         // across the lower face
        else if (double(domain.upper[a]) - x < c.dx) step = 1 - cells;    // across the upper face
        if (step == 0) continue;
        Key across = k;
        across[std::size_t(a)] += step;
        if (lattice.count(across)) continue;
        std::ostringstream s;
        s << "wall body '" << (groups.empty() ? std::string("wall") : groups[group].name) << "' lies across periodic axis "
          << axis_name(a) << ": it ends at the face " << axis_name(a) << " = "
          << double(step > 0 ? domain.lower[a] : domain.upper[a]) << " (its particle at (";
        for (int b = 0; b < D; ++b) s << (b ? ", " : "") << double(p.wall[w][b]);
        s << ") has no wall beside it across the face); a wall along a periodic axis must run through both faces (make "
             "its shape reach beyond the domain)";
        throw CaseFileError(periodic_where(c) + s.str());
      }
    }
  }
  // The domain's length along each periodic axis, 0 along the others.
  static Vec<T, D> period_of(const CaseDescription& c, const Box<T, D>& domain) {
    Vec<T, D> period{};
    for (int a : c.domain.periodic) period[a] = domain.upper[a] - domain.lower[a];
    return period;
  }
  // The cell lists' box: images->search_box() where an axis is periodic (the images lie beyond
  // the faces); in the general form the domain cut down to one cutoff around the particles the
  // case starts with. The cells cost 8 bytes each, and a domain drawn around a tank's walls at
  // its coarsest dx holds a margin of empty cells at a fine one (dambreak_general_3d.toml at dx
  // 0.00625: twice the cells, 11.5 bytes per particle). A particle that goes beyond (over an open
  // tank's rim) is clamped into a border cell and still found; leaving is counted against the
  // domain all the same (CellLinkedList::report_outside_of). Walls that move sweep beyond where
  // they start, and the short form's domain is its tank and walls: the domain there.
  static Box<T, D> search_box_of(const CaseDescription& c, const std::unique_ptr<PeriodicImages<T, D>>& images,
                                 const Box<T, D>& domain, const TankParticles<T, D>& p, T cutoff) {
    if (images) return images->search_box();
    if (!c.general() || c.walls_move() || (p.fluid.empty() && p.wall.empty())) return domain;
    // The general form is made whole on every rank (made_in_shares): one box on all of them.
    Box<T, D> box{p.fluid.empty() ? p.wall.front() : p.fluid.front(), p.fluid.empty() ? p.wall.front() : p.fluid.front()};
    for (const auto* set : {&p.fluid, &p.wall})
      for (const Vector& x : *set)
        for (int a = 0; a < D; ++a) {
          box.lower[a] = std::min(box.lower[a], x[a]);
          box.upper[a] = std::max(box.upper[a], x[a]);
        }
    for (int a = 0; a < D; ++a) {
      box.lower[a] = std::max(domain.lower[a], box.lower[a] - cutoff);
      box.upper[a] = std::min(domain.upper[a], box.upper[a] + cutoff);
    }
    return box;
  }
  // On several ranks a tank case (the short form, without obstacle files, and without initial
  // velocities kept through a settling stage) is made in shares: the domain is cut before the
  // particles are made, and each rank makes only the particles of its own cells, with the ids
  // the whole case gives them (TankLattice), so that no rank holds the whole case. Other cases
  // are made whole on every rank and each keeps its share (take_shares).
  static bool made_in_shares(const CaseDescription& c, const comm::Communicator* comm) {
    return comm && comm->size() > 1 && !c.general() && c.obstacles.empty() &&
           !(c.initial_fluid_state && c.settling_time > 0);
  }
  // The cut of a case made in shares: the fluid lattice's layers (along its last axis) spread
  // evenly over the ranks, each rank passing its own to the collective cut, which so sees
  // every fluid particle once: the cut the whole case gives.
  static std::optional<comm::Decomposition<D>> initial_cut_of(const CaseDescription& c, const comm::Communicator* comm,
                                                              const WendlandC2Kernel<T, D>& kernel) {
    if (!made_in_shares(c, comm)) return std::nullopt;
    const TankLattice<D> lattice(c.tank, c.column, c.dx);
    const long layers = lattice.fluid_layers();
    const long first = layers * comm->rank() / comm->size(), last = layers * (comm->rank() + 1) / comm->size();
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lower[3] = {-inf, -inf, -inf}, upper[3] = {inf, inf, inf};
    lower[D - 1] = double(first) * c.dx;  // layer k lies at (k + 1/2) dx
    upper[D - 1] = double(last) * c.dx;
    std::vector<Vec<Real, D>> x;
    x.reserve(std::size_t(lattice.fluid_count() / std::uint64_t(std::max<long>(1, layers)) * std::uint64_t(last - first)));
    lattice.fluid_within(lower, upper, [&](std::uint64_t, const double* q) {
      Vec<Real, D> y;
      for (int a = 0; a < D; ++a) y[a] = Real(T(q[a]));  // as the particle's T position is cut later
      x.push_back(y);
    });
    const comm::CellGrid<D> grid = RankShare<T, D>::grid_of(*comm, domain_of(c), kernel.cutoff(), kernel.h);
    return RankShare<T, D>::cut(*comm, grid, std::span<const Vec<Real, D>>(x));
  }
  // This rank's particles of a case made in shares: those of the lattice within the bounding
  // box of its cells that lie in its cells, in id order.
  static TankParticles<T, D> share_of(const CaseDescription& c, const comm::Decomposition<D>& cut, int rank) {
    const TankLattice<D> lattice(c.tank, c.column, c.dx);
    const comm::CellGrid<D>& grid = cut.grid();
    // Each cell's owner once (host kernels): a lattice point's owner is then its cell's entry.
    std::vector<std::int32_t> owner(grid.cell_count());
    particle_for(par, Index(owner.size()),
                 comm::decomposition_detail::CellOwners<D>{cut.view(seq), View<std::int32_t>(owner.data(), owner.size())});
    const auto index_of = [&](const Vec<int, D>& cell) {
      std::uint64_t k = 0;
      for (int a = D - 1; a >= 0; --a) k = k * std::uint64_t(grid.cells[a]) + std::uint64_t(cell[a]);
      return k;
    };
    Vec<int, D> first = grid.cells, last{};
    for (std::uint64_t n = 0; n < owner.size(); ++n) {
      if (owner[n] != rank) continue;
      const Vec<int, D> cell = comm::decomposition_detail::cell_of_index<D>(grid, n);
      for (int a = 0; a < D; ++a) first[a] = std::min(first[a], cell[a]), last[a] = std::max(last[a], cell[a] + 1);
    }
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lower[3] = {-inf, -inf, -inf}, upper[3] = {inf, inf, inf};
    bool none = false;
    for (int a = 0; a < D; ++a) {
      none = none || first[a] >= last[a];
      // A cell's faces widened by a little: the owner decides below (edge cells take what lies beyond).
      const double margin = 1e-6 * double(grid.cell_size[a]);
      if (first[a] > 0) lower[a] = double(grid.box.lower[a]) + first[a] * double(grid.cell_size[a]) - margin;
      if (last[a] < grid.cells[a]) upper[a] = double(grid.box.lower[a]) + last[a] * double(grid.cell_size[a]) + margin;
    }
    TankParticles<T, D> p;
    p.fluid_whole = lattice.fluid_count();
    p.wall_whole = lattice.wall_count();
    if (none) return p;
    const auto mine = [&](const double* q, Vec<T, D>& x) {
      Vec<Real, D> y;
      for (int a = 0; a < D; ++a) x[a] = T(q[a]), y[a] = Real(x[a]);
      return owner[index_of(grid.cell_of(y))] == rank;
    };
    lattice.fluid_within(lower, upper, [&](std::uint64_t id, const double* q) {
      Vec<T, D> x{};
      if (!mine(q, x)) return;
      p.fluid.push_back(x);
      p.fluid_numbers.push_back(id);
    });
    lattice.walls_within(lower, upper, [&](std::uint64_t id, const double* q, const double* normal) {
      Vec<T, D> x{}, n{};
      if (!mine(q, x)) return;
      for (int a = 0; a < D; ++a) n[a] = T(normal[a]);
      p.wall.push_back(x);
      p.wall_normal.push_back(n);
      p.wall_numbers.push_back(id);
    });
    return p;
  }
  static TankParticles<T, D> particles_of(const CaseDescription& c, PolicyKind kind, const comm::Communicator* comm,
                                          const std::optional<comm::Decomposition<D>>& cut) {
    if (cut) return share_of(c, *cut, comm->rank());
    TankParticles<T, D> p;
    if (c.general()) {
      p = visit_policy(kind, [&](auto policy) { return make_body_particles<T, D>(policy, c); });
    } else {
      p = make_tank_particles<T, D>(c.tank, c.column, c.dx);
    }
    add_obstacles(p, c);
    return p;
  }
  // Each wall body's name and particle count, in the order of the wall's ids.
  static std::vector<WallBodyCount> wall_groups_of(const CaseDescription& c, const TankParticles<T, D>& p) {
    std::vector<WallBodyCount> groups;
    if (c.general()) {
      for (const auto& [name, count] : p.wall_groups) groups.push_back({name, Index(count)});
      for (std::size_t k = 0; k < p.obstacle_wall_counts.size(); ++k)
        groups.push_back({"obstacle_" + std::to_string(k + 1), Index(p.obstacle_wall_counts[k])});
    } else {
      std::size_t obstacles = 0;
      for (std::size_t n : p.obstacle_wall_counts) obstacles += n;
      groups.push_back({"tank", Index((p.wall_whole ? p.wall_whole : p.wall.size()) - obstacles)});
      for (std::size_t k = 0; k < p.obstacle_wall_counts.size(); ++k)
        groups.push_back({"obstacle_" + std::to_string(k + 1), Index(p.obstacle_wall_counts[k])});
    }
    return groups;
  }
  // The fluid particle nearest the fluid's centroid: a point of the water.
  static Vector seed_of(const TankParticles<T, D>& p) {
    if (p.fluid.empty()) return Vector{};
    Vec<double, D> centroid{};
    for (const Vector& x : p.fluid)
      for (int a = 0; a < D; ++a) centroid[a] += double(x[a]) / double(p.fluid.size());
    Vector seed = p.fluid.front();
    double nearest = std::numeric_limits<double>::max();
    for (const Vector& x : p.fluid) {
      double d = 0;
      for (int a = 0; a < D; ++a) d += (double(x[a]) - centroid[a]) * (double(x[a]) - centroid[a]);
      if (d < nearest) nearest = d, seed = x;
    }
    return seed;
  }
  // The short form keeps the tank's own box (tank_particles.hpp); the general form cuts the
  // domain down around the water, wall particle by wall particle (WallFreeBox::around).
  static WallFreeBox<T, D> wall_free_of(const CaseDescription& c, const TankParticles<T, D>& p, const Box<T, D>& domain,
                                        double cutoff) {
    if (!c.general()) return WallFreeBox<T, D>::of_tank(c.tank, p.wall, cutoff);
    if (c.walls_move()) return WallFreeBox<T, D>::empty();  // made in make_wall_motions, from the swept boxes
    const Vector seed = seed_of(p);
    if (c.domain.periodic.empty()) return WallFreeBox<T, D>::around(p.wall, domain.lower, domain.upper, seed, cutoff);
    // Periodic axes: the wall particles and their images (+-L where within 1.1 cutoffs of a
    // face), in a start box reaching 2 cutoffs beyond the periodic faces (fluid drifts a little
    // past a face between wraps).
    std::vector<Vec<T, D>> walls = p.wall;
    Vec<T, D> lower = domain.lower, upper = domain.upper;
    for (int a : c.domain.periodic) {
      const T length = domain.upper[a] - domain.lower[a];
      lower[a] -= T(2 * cutoff);
      upper[a] += T(2 * cutoff);
      const std::size_t n = walls.size();
      for (std::size_t k = 0; k < n; ++k) {
        Vec<T, D> w = walls[k];
        if (double(w[a] - domain.lower[a]) < 1.1 * cutoff) w[a] += length, walls.push_back(w);
        else if (double(domain.upper[a] - w[a]) < 1.1 * cutoff) w[a] -= length, walls.push_back(w);
      }
    }
    return WallFreeBox<T, D>::around(walls, lower, upper, seed, cutoff);
  }

  State(const CaseDescription& c, PolicyKind kind, bool settle_now, const comm::Communicator* comm)
      : description(checked(c)),
        policy(kind),
        kernel(WendlandC2Kernel<T, D>::from_spacing(T(c.dx), T(c.smoothing_length_ratio))),
        initial_cut(initial_cut_of(description, comm, kernel)),
        particles(particles_of(description, kind, comm, initial_cut)),
        wall_groups(wall_groups_of(c, particles)),
        obstacle_counts(particles.obstacle_wall_counts.begin(), particles.obstacle_wall_counts.end()),
        removed_fluid(particles.removed_fluid),
        relaxed(particles.relaxed),
        domain(domain_of(c)),
        fluid_body("Water", domain, particles.fluid.size(), 0, 0, {particles.fluid_whole, particles.fluid_numbers}),
        wall_body("Wall", domain, particles.wall.size(), 0, 0, {particles.wall_whole, particles.wall_numbers}),
        fluid(fluid_body),
        wall(wall_body),
        fluid_images(images_of(c, fluid_body, domain, kernel.cutoff())),
        wall_images(images_of(c, wall_body, domain, kernel.cutoff())),
        search_box(search_box_of(c, fluid_images, domain, particles, kernel.cutoff())),
        fluid_cells(fluid.position, search_box, kernel.cutoff(), OutsideParticles::clamp, cell_size_of(c, kind, kernel.cutoff())),
        wall_cells(wall.position, search_box, kernel.cutoff(), OutsideParticles::clamp, cell_size_of(c, kind, kernel.cutoff())),
        inner(fluid_cells, search_method_of(c)),
        contact(fluid.position, wall_cells, search_method_of(c)),
        fluid_sorter(fluid_body.particles(), fluid.position, fluid_cells.grid(), 1, SortOrder::cell_index_then_id),
        wall_sorter(wall_body.particles(), wall.position, wall_cells.grid(), 1, SortOrder::cell_index_then_id),
        eos{T(c.density), T(c.sound_speed)},
        riemann(AcousticRiemannSolver<T>::make(T(c.density), T(c.sound_speed))),
        wall_volume(volume_of(c.dx)),
        criteria{double(kernel.h), c.reference_velocity, c.sound_speed, c.viscosity / c.density},
        density_summation(fluid, inner, contact, kernel, T(c.dx), T(c.density),
                          c.free_surface_density == "carried" ? SurfaceDensity::carried
                          : c.free_surface_density == "none" ? SurfaceDensity::none
                                                             : SurfaceDensity::reference),
        prior_acceleration(fluid, wall, inner, contact, kernel, gravity_of(c), T(c.viscosity), wall_volume, T(c.dx)),
        pressure_start(fluid, eos),
        wall_free(wall_free_of(c, particles, domain, double(kernel.cutoff()))),
        pressure_relaxation(fluid, wall, inner, contact, kernel, riemann, wall_volume, wall_free),
        velocity_update(fluid),
        density_relaxation(fluid, wall, inner, contact, kernel, riemann, wall_volume, c.continuity_dissipation, wall_free,
                           DensityDiffusion<T, D>::make(T(c.density_diffusion), kernel.h, T(c.sound_speed), T(c.density),
                                                        gravity_of(c)),
                           c.wall_continuity == "kernel_sum" ? WallContinuity::kernel_sum : WallContinuity::mirror),
        density_update(fluid),
        max_speed(fluid),
        velocity_update_and_max_speed(velocity_update, max_speed),
        velocity_damping(fluid),
        density_update_and_start(density_update, pressure_start),
        refresh_records(fluid),
        observers(fluid, gravity_of(c), 0, T(c.dx), !(comm && comm->size() > 1), period_of(c, domain),
                  comm && comm->size() > 1) {
    // Neighbours in one order on any number of ranks: cells in the stencil's order, particles
    // within a cell by global id (owned or ghost alike); the sorters' (cell, id) order keeps the
    // lists' contiguous path where a set has no ghosts.
    fluid_cells.order_within_cells_by_id(fluid_body.particles());
    wall_cells.order_within_cells_by_id(wall_body.particles());
    density_summation.set_wall_free(wall_free);  // declared before the box: set here
    if (!fluid_images) fluid_cells.report_outside_of(domain);  // the cells may cover less (search_box_of)
    if (particles.fluid.empty() && particles.fluid_whole == 0)
      throw Error("case '" + c.name + "': the fluid holds no particle at dx = " + std::to_string(c.dx) +
                  (removed_fluid ? " (the obstacles took all " + std::to_string(removed_fluid) + ")" : std::string()));
    for (const ProbeDescription& p : c.probes) {
      Vector x{};
      for (int a = 0; a < D; ++a) x[a] = T(p.position[a]);
      observers.add_probe(x, WendlandC2Kernel<T, D>::from_spacing(T(c.dx * p.kernel_width)));
    }
    check_walls_along_periodic_axes(c, particles, domain, wall_groups, double(kernel.cutoff()));
    make_wall_motions(c);
    if (c.wall_pressure == "averaged") {
      // Each wall particle's pressure is averaged from the fluid particles around it; ranks and
      // periodic images would need those pressures exchanged like the fluid's, which is not built.
      if (!c.domain.periodic.empty())
        throw CaseFileError(periodic_where(c) + "fluid.wall_pressure = \"averaged\" runs on one rank without periodic " +
                            "axes (the walls' averaged pressures are not carried across periodic faces)");
      if (comm && comm->size() > 1)
        throw CaseFileError(c.source + ": key 'fluid.wall_pressure': \"averaged\" runs on one rank without periodic " +
                            "axes (the walls' averaged pressures are not exchanged between ranks)");
      wall.pressure = &wall_body.particles().template add_variable<T>("WallPressure");
      wall_pressure_average =
          std::make_unique<WallPressureAverage<T, D>>(fluid, wall, fluid_cells, kernel, gravity_of(c));
    }
    if (c.kernel_gradient_correction) {
      kernel_correction = &fluid_body.particles().template add_variable<Mat<T, D>>(kernel_correction_name.front());
      kernel_correction_matrices = std::make_unique<KernelCorrectionMatrices<T, D>>(
          fluid, inner, contact, kernel, wall_volume, wall_free, *kernel_correction);
      corrected_pressure_relaxation =
          std::make_unique<CorrectedPressureRelaxation<T, D>>(pressure_relaxation, *kernel_correction);
    }
    if (c.particle_shifting > 0) {
      shifting_kernel_sum = &fluid_body.particles().template add_variable<T>(shifting_kernel_sum_name.front());
      shifting_kernel_sums = std::make_unique<ShiftingKernelSum<T, D>>(fluid, inner, contact, kernel, T(c.dx),
                                                                       wall_volume, *shifting_kernel_sum);
      particle_shifting = std::make_unique<ParticleShifting<T, D>>(fluid, inner, contact, kernel, wall_volume,
                                                                   T(c.particle_shifting), *shifting_kernel_sum);
    }
    if (c.loads) make_wall_load(c);
    if (c.damping_zone.present()) {
      Vector e{};
      for (int a = 0; a < D; ++a) e[a] = T(c.damping_zone.direction[std::size_t(a)]);
      damping_zone = std::make_unique<DampingZone<T, D>>(
          fluid, e, T(c.damping_zone.start), T(c.damping_zone.end), T(c.damping_zone.strength),
          c.damping_zone.form == "exponential" ? DampingForm::exponential : DampingForm::linear);
    }
    if (!c.velocity_probes.empty()) {
      std::vector<VelocityProbePoint<T, D>> points;
      for (const VelocityProbeDescription& v : c.velocity_probes) {
        Vector x{};
        for (int a = 0; a < D; ++a) x[a] = T(v.position[std::size_t(a)]);
        points.push_back({v.name, x});
      }
      velocity_probes = std::make_unique<VelocityProbes<T, D>>(fluid, fluid_cells, kernel, points);
    }
    if (!c.gauges.empty()) {
      std::vector<WaveGaugeLine<T, D>> lines;
      for (const GaugeDescription& g : c.gauges) {
        Vector x{};
        for (int a = 0; a < D; ++a) x[a] = T(g.position[std::size_t(a)]);
        lines.push_back({g.name, x, T(g.bottom), T(g.top)});
      }
      try {
        gauges = std::make_unique<WaveGauges<T, D>>(fluid, fluid_cells, kernel, T(c.dx), gravity_of(c), lines);
      } catch (const CaseFileError&) {
        throw;
      } catch (const Error& e) {
        throw CaseFileError(c.source + ":" + std::to_string(c.gauges.front().line) + ": key 'gauge': " + e.what());
      }
    }
    if (comm && comm->size() > 1) {
      MemorySpace space = MemorySpace::host;
      visit_policy(policy, [&](auto p) { space = decltype(p)::space; });
      // The skin: a particle moves at most 0.25 h per advection step while its speed holds
      // (Dt = 0.25 h / |v|max); h leaves room for speeds that double within the step.
      Vec<int, D> periodic{};
      for (int a : c.domain.periodic) periodic[a] = 1;
      share = std::make_unique<RankShare<T, D>>(*comm, domain, kernel.cutoff(), kernel.h, space, rebalance_fraction,
                                                periodic);
      overlap_refreshes = share->overlap_refreshes();
      const bool ghost_merge = RankShare<T, D>::ghost_merge();
      fluid_cells.sort_only_ghosts(ghost_merge);
      wall_cells.sort_only_ghosts(ghost_merge);
      if (overlap_refreshes && RankShare<T, D>::owned_views()) {
        // The interior particles' passes search the owned particles alone (with_current_records).
        fluid_cells.keep_owned_view(fluid_body.particles());
        wall_cells.keep_owned_view(wall_body.particles());
      }
      // Along periodic axes the halo holds the images across the faces, the own rank's among
      // them; the images' object only wraps the fluid into the box (and gave the cells' box).
      rank_wrap = std::move(fluid_images);
      wall_images.reset();
      // Nothing on several ranks looks a particle up by id: no map over the whole set's ids.
      fluid_body.particles().drop_index_of_id();
      wall_body.particles().drop_index_of_id();
    }
    const auto made = std::chrono::steady_clock::now();
    making_seconds = std::chrono::duration<double>(made - constructed_from).count();
    initialise();
    placing_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - made).count();
    if (settle_now) settle();
  }

  // Several ranks: the owned fluid counts may drift this far above their mean (max / mean - 1)
  // before the domain is cut anew.
  static constexpr double rebalance_fraction = 0.1;

  // The largest of the ranks' values (one rank: x). A non-finite value on any rank gives +inf
  // on all, so that every rank takes the same branch.
  // The host's time in it (the device is done: x came from it) is this rank's wait for the
  // slowest rank plus the reduction's latency (speed_wait_seconds).
  double global_max(double x) {
    if (!share) return x;
    const auto start = std::chrono::steady_clock::now();
    const double m = share->comm().allreduce_max(std::isfinite(x) ? x : std::numeric_limits<double>::infinity());
    speed_wait_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return m;
  }
  std::uint64_t global_sum(std::uint64_t x) const { return share ? share->comm().allreduce_sum(x) : x; }
  double global_sum(double x) const { return share ? share->comm().allreduce_sum(x) : x; }

  // A run that cannot go on. On several ranks every rank calls this at the same point (the
  // condition is global), and every rank stops with rank 0's line (comm::RankFailure).
  [[noreturn]] void fail(const std::string& message) {
    if (share) share->comm().check_all(share->comm().rank() != 0, message);
    throw SimulationError(message);
  }

  // Several ranks: the ghosts' positions and neighbour records from their owners, before a pass
  // that reads them.
  template <class P>
  void refresh_ghost_records(P p) {
    share->refresh(p, fluid_body, *fluid_halo, ghost_record_names);
    shift_ghost_image_records(p);
  }
  // A periodic image's record holds its source's position: shift it as the position was.
  template <class P>
  void shift_ghost_image_records(P p) {
    const Index ghosts = fluid_body.particles().ghost_count();
    if (share->periodic() && ghosts > 0)
      particle_for(p, ghosts,
                   GhostRecordPositions<T, D>{fluid.position.read(p), fluid.neighbor_position_volume.read_write(p),
                                              fluid.size()});
  }
  // Several ranks: wall particles to the owners of their cells, sorted, their ghosts gathered,
  // binned (after a rebalance, and after moving walls moved).
  template <class P>
  void redistribute_walls(P p, bool sort_now) {
    share->migrate(p, wall_body);
    if (sort_now) wall_sorter.sort(p);
    share->gather(p, wall_body, wall_halo);
    wall_cells.build(p);
  }

  // The law of one motion description (case_description.hpp); angles in degrees become radians.
  TimeLaw law_of(const MotionDescription& m, bool angle, MemorySpace space, const std::string& where) {
    const double unit = angle ? std::numbers::pi / 180.0 : 1.0;
    if (m.law == "constant") return constant_rate_law(Real(m.rate * unit), where);
    if (m.law == "sinusoid")
      return sinusoid_law(Real(m.amplitude * unit), Real(m.period), Real(m.phase * std::numbers::pi / 180.0),
                          Real(m.ramp_periods), Real(m.start), where);
    MotionTableRows rows = read_motion_table_csv(m.file);
    for (double& v : rows.value) v *= unit;
    motion_tables.push_back(std::make_unique<MotionTable>(rows));
    return motion_tables.back()->law(space);
  }

  // The prescribed motions of the wall bodies (moving_walls.hpp): motion 0 is rest, then one per
  // moving body, and each wall particle gets its body's. Nothing is registered, and the kernels
  // keep their static-wall path, when no body moves. A bad motion is one CaseFileError line.
  void make_wall_motions(const CaseDescription& c) {
    if (!c.walls_move()) return;
    if (wall_images) throw CaseFileError(periodic_where(c) + "moving walls are not available in a periodic domain yet");
    MemorySpace space = MemorySpace::host;
    visit_policy(policy, [&](auto p) { space = decltype(p)::space; });
    std::vector<StoredRigidMotion<D>> list{StoredRigidMotion<D>::of(fixed_motion<D>())};
    std::vector<RigidMotion<D>> on_host{fixed_motion<D>()};  // the same, a table's knots in host memory
    std::vector<std::uint32_t> of_group;  // per wall group (the wall bodies in order, then obstacles)
    const auto vec = [](const std::vector<double>& v) {
      Vecd<D> x{};
      for (int a = 0; a < D; ++a) x[a] = Real(v[std::size_t(a)]);
      return x;
    };
    for (const BodyDescription& b : c.bodies) {
      if (b.kind != "wall") continue;
      if (!b.moves()) {
        of_group.push_back(0);
        continue;
      }
      const MotionDescription& m = b.translation.moves() ? b.translation : b.rotation;
      const std::string key = b.translation.moves() ? "body.translation" : "body.rotation";
      try {
        Translation<D> translation = no_translation<D>();
        Rotation<D> rotation = no_rotation<D>();
        // The law in the policy's memory, and on the host (a table's knots there too).
        const auto laws_of = [&](const MotionDescription& m, bool angle) {
          const TimeLaw law = law_of(m, angle, space, "law");
          const TimeLaw host = m.law == "table" ? motion_tables.back()->law(MemorySpace::host) : law;
          return std::pair{law, host};
        };
        Translation<D> host_translation = translation;
        Rotation<D> host_rotation = rotation;
        if (b.translation.moves()) {
          const auto [law, host] = laws_of(b.translation, false);
          translation = make_translation<D>(vec(b.translation.direction), law, "direction");
          host_translation = translation, host_translation.law = host;
        }
        if (b.rotation.moves()) {
          const auto [law, host] = laws_of(b.rotation, true);
          if constexpr (D == 3) {
            rotation = make_rotation(vec(b.rotation.pivot), vec(b.rotation.axis), law, "axis");
          } else {
            rotation = make_rotation(vec(b.rotation.pivot), law, "pivot");
          }
          host_rotation = rotation, host_rotation.law = host;
        }
        list.push_back(StoredRigidMotion<D>::of(rigid_motion<D>(translation, rotation)));
        on_host.push_back(rigid_motion<D>(host_translation, host_rotation));
      } catch (const CaseFileError&) {
        throw;
      } catch (const Error& e) {
        throw CaseFileError(c.source + ":" + std::to_string(m.line) + ": key '" + key + "' (body '" + b.name + "'): " + e.what());
      }
      of_group.push_back(std::uint32_t(list.size() - 1));
    }
    while (of_group.size() < wall_groups.size()) of_group.push_back(0);  // the obstacles
    motions.assign(list);
    wall_motion = std::make_unique<WallMotionVariables<T, D>>(wall_body);
    wall.velocity = &wall_motion->velocity;
    wall.acceleration = &wall_motion->acceleration;
    // Ids: the first group's particles, then the second's, ... (the particles are still in that order).
    View<std::uint32_t> index = wall_motion->motion.write(MemorySpace::host);
    Index k = 0;
    for (std::size_t g = 0; g < wall_groups.size(); ++g)
      for (Index n = 0; n < wall_groups[g].count; ++n) index[k++] = of_group[g];
    move_walls = std::make_unique<MoveWalls<T, D>>(wall, *wall_motion, motions);
    // The wall-free box (wall_free_box.hpp) kept clear of every place a wall particle may take:
    // a moving one's swept box (rigid_motion.hpp), over all times; none where one moves without
    // bound. (wall_free_of left it empty.) The whole case's walls are here (the general form is
    // made whole on every rank before it is shared out), in id order, as `index`.
    std::vector<typename WallFreeBox<T, D>::Extent> extents(particles.wall.size());
    for (std::size_t q = 0; q < extents.size(); ++q) {
      Vecd<D> x0{};
      for (int a = 0; a < D; ++a) x0[a] = Real(particles.wall[q][a]);
      const SweptBox<D> swept = swept_box(on_host[index[Index(q)]], x0);
      if (!swept.bounded) return;
      for (int a = 0; a < D; ++a) extents[q].lower[a] = double(swept.lower[a]), extents[q].upper[a] = double(swept.upper[a]);
    }
    wall_free = WallFreeBox<T, D>::around(extents, domain.lower, domain.upper, seed_of(particles), double(kernel.cutoff()));
    density_summation.set_wall_free(wall_free);
    pressure_relaxation.set_wall_free(wall_free);
    density_relaxation.set_wall_free(wall_free);
  }

  // report.loads: the loads on every wall body (sph/wall_load.hpp), through the solver's own
  // contact relation, evaluated after each pressure relaxation.
  void make_wall_load(const CaseDescription& c) {
    if (wall_groups.empty() || wall_body.particles().owned_count() == 0)
      throw CaseFileError(c.source + ": key 'report.loads': the case has no wall body to load");
    std::vector<Index> counts;
    for (const WallBodyCount& g : wall_groups) counts.push_back(g.count);
    Vector point{};
    for (int a = 0; a < D; ++a) point[a] = T(c.moment_point.empty() ? 0.0 : c.moment_point[std::size_t(a)]);
    wall_load = std::make_unique<WallLoad<T, D>>(fluid, wall, wall_body.particles().ids(), wall_body.particles().first_id(),
                                                 counts, contact, kernel, riemann, wall_volume, point);
    if (kernel_correction) wall_load->use_correction(*kernel_correction);
  }
  // Adds dt times the loads of the current state (after a pressure relaxation) to the step's sum.
  template <class P>
  void sample_loads(P p, double dt) {
    if (!wall_load) return;
    const std::vector<WallBodyLoad<T, D>> now = wall_load->exec(p);
    if (load_sum.size() != now.size()) load_sum.assign(now.size(), WallBodyLoad<double, D>{});
    for (std::size_t b = 0; b < now.size(); ++b) {
      for (int a = 0; a < D; ++a) load_sum[b].force[a] += dt * double(now[b].force[a]);
      for (int a = 0; a < moment_components<D>; ++a) load_sum[b].moment[a] += dt * double(now[b].moment[a]);
    }
    load_time += dt;
  }
  void finish_loads() {
    if (!wall_load || !(load_time > 0)) return;
    if (share)  // each rank summed the loads of its own fluid particles
      for (WallBodyLoad<double, D>& b : load_sum) {
        for (int a = 0; a < D; ++a) b.force[a] = global_sum(b.force[a]);
        for (int a = 0; a < moment_components<D>; ++a) b.moment[a] = global_sum(b.moment[a]);
      }
    step_loads.assign(load_sum.size(), WallLoadSample{});
    for (std::size_t b = 0; b < load_sum.size(); ++b) {
      for (int a = 0; a < D; ++a) step_loads[b].force.push_back(load_sum[b].force[a] / load_time);
      for (int a = 0; a < moment_components<D>; ++a) step_loads[b].moment.push_back(load_sum[b].moment[a] / load_time);
    }
    load_sum.assign(load_sum.size(), WallBodyLoad<double, D>{});
    load_time = 0;
  }

  // Moving walls: their state at time t (or, while they are held, at rest where they start).
  template <class P>
  void place_walls(P p, double t) {
    if (move_walls && !walls_held) move_walls->exec(p, Real(t));
  }

  // The settling stage (case_description.hpp): the run's own steps with the velocity damped,
  // until settling_time; then the water starts at rest from there, at time 0, step 0.
  void settle() {
    if (!(description.settling_time > 0)) return;
    const auto start = std::chrono::steady_clock::now();
    damping_rate = description.settling_damping;
    while (time < description.settling_time * (1 - 1e-12)) advance(description.settling_time);
    damping_rate = 0;
    {
      // The water leaves the settling stage with its initial velocity (the fluid bodies' and
      // initial_fluid_state's; zero where none was given), as if it had started there.
      View<Vector> v = fluid.velocity.write(MemorySpace::host);
      View<T> drho = fluid.density_change_rate.write(MemorySpace::host);
      View<const std::uint64_t> id = fluid_body.particles().ids().read(MemorySpace::host);
      const std::uint64_t first = fluid_body.particles().first_id();
      for (Index i = 0; i < v.size(); ++i) {
        v[i] = initial_velocity.empty() ? Vector{} : initial_velocity[id[i] - first];
        drho[i] = T(0);
      }
      initial_velocity = {};
    }
    visit_policy(policy, [&](auto p) {
      refresh_records.exec(p);
      if (share) refresh_ghost_records(p);
      if (move_walls) {
        // The walls leave their hold: their state at time 0 (a table may start displaced).
        walls_held = false;
        place_walls(p, 0.0);
        if (share) redistribute_walls(p, true);
        else build_wall(p);
        rebuild(p);
      }
    });
    settling = {time, advection_steps, acoustic_steps,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
    time = 0;
    advection_steps = 0;
    acoustic_steps = 0;
  }

  void initialise() {
    const Index n = particles.fluid.size();
    {
      View<Vector> x = fluid.position.write(MemorySpace::host);
      View<Vector> v = fluid.velocity.write(MemorySpace::host);
      View<T> rho = fluid.density.write(MemorySpace::host);
      View<T> p = fluid.pressure.write(MemorySpace::host);
      View<T> m = fluid.mass.write(MemorySpace::host);
      View<T> drho = fluid.density_change_rate.write(MemorySpace::host);
      // The hydrostatic start: p = rho0 |g| (level of the surface - level of x), levels measured
      // along -g (the short form: heights along y, as before).
      const double surface = description.general() ? description.free_surface : description.column[1];
      const Vector g = gravity_of(description);
      const auto level = [&](const Vector& p) {
        if (!description.general()) return double(p[1]);
        double along = 0;
        for (int a = 0; a < D; ++a) along -= double(g[a]) * double(p[a]);
        return along / description.gravity;
      };
      std::vector<double> point(D), velocity(D);
      for (Index i = 0; i < n; ++i) {
        x[i] = particles.fluid[i];
        v[i] = particles.fluid_velocity.empty() ? Vector{} : particles.fluid_velocity[i];
        double pressure =
            description.hydrostatic ? description.density * description.gravity * (surface - level(x[i])) : 0.0;
        if (description.initial_fluid_state) {
          for (int a = 0; a < D; ++a) point[std::size_t(a)] = double(x[i][a]), velocity[std::size_t(a)] = double(v[i][a]);
          description.initial_fluid_state(point, velocity, pressure);
          if (velocity.size() != std::size_t(D))
            throw Error("case '" + description.name + "': initial_fluid_state gave " + std::to_string(velocity.size()) +
                        " velocity components; the case is " + std::to_string(D) + "D");
          for (int a = 0; a < D; ++a) v[i][a] = T(velocity[std::size_t(a)]);
        }
        if (description.settling_time > 0 && !(v[i] == Vector{})) {
          if (initial_velocity.empty()) initial_velocity.assign(n, Vector{});
          initial_velocity[i] = v[i];  // by id: the particles are in id order here
          v[i] = Vector{};             // the settling starts at rest
        }
        p[i] = T(pressure);
        rho[i] = eos.density(T(pressure));
        m[i] = rho[i] * wall_volume;
        drho[i] = T(0);
      }
    }
    {
      View<Vector> x = wall.position.write(MemorySpace::host);
      View<Vector> nrm = wall.normal.write(MemorySpace::host);
      for (Index i = 0; i < particles.wall.size(); ++i) {
        x[i] = particles.wall[i];
        nrm[i] = particles.wall_normal[i];
      }
    }
    particles = {};
    if (wall_motion) {
      // The reference state: where each particle is with its motion at rest, at rest.
      View<const Vector> x = wall.position.read(MemorySpace::host);
      View<const Vector> nrm = wall.normal.read(MemorySpace::host);
      View<Vector> x0 = wall_motion->initial_position.write(MemorySpace::host);
      View<Vector> n0 = wall_motion->initial_normal.write(MemorySpace::host);
      View<Vector> v = wall_motion->velocity.write(MemorySpace::host);
      View<Vector> a = wall_motion->acceleration.write(MemorySpace::host);
      for (Index i = 0; i < x.size(); ++i) {
        x0[i] = x[i];
        n0[i] = nrm[i];
        v[i] = Vector{};
        a[i] = Vector{};
      }
      // Held where they start (at rest) through the settling stage, if there is one.
      walls_held = description.settling_time > 0;
    }
    visit_policy(policy, [&](auto p) {
      place_walls(p, 0.0);
      if (share) {
        // Each rank made its share (made_in_shares), or the whole case (the same particles and
        // ids on every rank) and keeps its share.
        take_shares(p);
        return;
      }
      wall_sorter.sort(p);
      build_wall(p);
      fluid_sorter.sort(p);
      rebuild(p);
    });
  }

  // Several ranks, sets made whole on every rank (at the start, or restored from a checkpoint):
  // cut the domain from the fluid, keep each rank's share of fluid and walls, sort them, gather
  // their ghosts and build the neighbour structures.
  template <class P>
  void take_shares(P p) {
    if (initial_cut) {
      // Made in shares: the cut the particles were made for.
      share->adopt(std::move(*initial_cut));
      initial_cut.reset();
    } else {
      share->decompose(fluid_body);
      // On the host, where the particles were made or restored: a device then takes memory for
      // this rank's share only (its copies are allocated at their first access, after this).
      share->keep_owned(par, fluid_body);
      share->keep_owned(par, wall_body);
    }
    wall_sorter.sort(p);
    share->gather(p, wall_body, wall_halo);
    wall_cells.build(p);
    fluid_sorter.sort(p);
    share->gather(p, fluid_body, fluid_halo);
    rebuild(p);
  }

  // The wall's cell list, after its images where an axis is periodic (the wall does not move:
  // once, and after a restore).
  template <class P>
  void build_wall(P p) {
    if (wall_images) {
      wall_images->build(p);
      wall_images->refresh(p, wall.normal);
    }
    wall_cells.build(p);
  }

  // Before a relaxation pass (periodic axes only): the images' positions and neighbour records
  // from their sources' current ones.
  template <class P>
  void refresh_image_records(P p) {
    PeriodicImages<T, D>& images = *fluid_images;
    if (images.ghost_count() == 0) return;
    RefreshImageRecords<T, D> k{images.sources().read(p),
                                images.codes().read(p),
                                fluid.position.read_write(p),
                                fluid.neighbor_position_volume.read_write(p),
                                fluid.neighbor_velocity_pressure.read_write(p),
                                {},
                                fluid.size()};
    for (unsigned code = 0; code < image_code_count<D>; ++code) k.shift[code] = images.shift(code);
    particle_for(p, images.ghost_count(), k);
  }

  template <class P>
  void rebuild(P p) {
    if (fluid_images) {
      // Owned particles wrapped into the box (the caller wraps before a sort), their images
      // made, and what the first pass of the next step reads at them (density summation: mass,
      // positions; prior acceleration: velocity, and density after the summation).
      fluid_images->build(p);
      fluid_images->refresh(p, fluid.mass, fluid.velocity);
      inner.set_source_count(fluid.size());
      contact.set_source_count(fluid.size());
    }
    if (share) {
      // Ghosts from other ranks are neighbours, never sources.
      inner.set_source_count(fluid.size());
      contact.set_source_count(fluid.size());
      // Ghosts (other ranks' particles, periodic images) may lie outside the cells' box by
      // design: only the owned particles are checked for leaving the domain.
      fluid_cells.report_only_first(fluid.size());
    }
    fluid_cells.build(p);
    if (share && overlap_refreshes) {
      // Where the interior particles' passes search the owned particles alone (exec_listed),
      // the interior reaches to cutoff + skin from the other ranks' cells (InteriorSplit).
      const bool owned_only = fluid_cells.owned_view_ready() && wall_cells.owned_view_ready();
      fluid_split.build(p, share->decomposition(), fluid.position.read(p).subview(0, fluid.size()),
                        owned_only ? Real(share->width()) : Real(0));
    }
    // With stored lists, dW/dr of each pair is cached with its geometry (the relaxations read it).
    inner.update(p, PairKernelDerivative<T, D>{kernel});
    contact.update(p, PairKernelDerivative<T, D>{kernel});
    // After a sort or a restore the neighbour records follow the new order: the density
    // summation, first to read them, reads those of the images and ghosts too.
    refresh_records.exec(p);
    if (fluid_images) refresh_image_records(p);
    if (share) refresh_ghost_records(p);
    const CellListReport report = fluid_cells.report();
    // On several ranks the counts of all ranks' owned particles.
    const std::uint64_t non_finite = global_sum(std::uint64_t(report.non_finite));
    const std::uint64_t out_of_box = global_sum(std::uint64_t(report.out_of_box));
    if (non_finite != 0 || (out_of_box != 0 && description.domain.leaving != "remove"))
      diagnose("a fluid particle left the domain");
    if (out_of_box != 0) {
      remove_leaving(p);
      if (share) share->gather(p, fluid_body, fluid_halo);
      rebuild(p);
    }
  }

  // Removes the fluid particles outside the domain (domain.leaving = "remove"): the others keep
  // their order, the removed ones are counted with their mass, and the neighbour structures
  // are rebuilt by the caller. Host code: particles leave rarely, so a copy there costs little.
  template <class P>
  void remove_leaving(P p) {
    ParticleSet& set = fluid_body.particles();
    if (set.ghost_count() != 0) set.set_ghost_count(0);  // images are rebuilt after the removal
    const Index n = set.owned_count();
    std::vector<std::uint32_t> order;
    order.reserve(n);
    Index kept = 0;
    {
      View<const Vector> x = fluid.position.read(MemorySpace::host);
      View<const T> m = fluid.mass.read(MemorySpace::host);
      for (Index i = 0; i < n; ++i)
        if (domain.contains(x[i])) order.push_back(std::uint32_t(i));
      kept = Index(order.size());
      for (Index i = 0; i < n; ++i)
        if (!domain.contains(x[i])) {
          order.push_back(std::uint32_t(i));
          removed_mass += double(m[i]);
        }
    }
    removed_particles += Index(global_sum(std::uint64_t(n - kept)));
    if (share) {
      double mass = 0;
      View<const T> m = fluid.mass.read(MemorySpace::host);
      for (std::size_t k = kept; k < order.size(); ++k) mass += double(m[order[k]]);
      removed_mass += global_sum(mass) - mass;  // the other ranks' (this rank's is counted above)
    }
    if (global_sum(std::uint64_t(kept)) == 0) diagnose("every fluid particle has left the domain");
    DiscreteVariable<std::uint32_t> permutation("RemovalOrder");
    permutation.assign(order);
    set.reorder(p, permutation.read(p));
    set.shrink_owned(p, kept);
  }

  // Finds the first particle with a non-finite value or outside the domain and throws.
  [[noreturn]] void diagnose(const std::string& what) {
    std::ostringstream s;
    if (damping_rate > 0) s << "settling ";  // before time 0 (settle())
    s << "step " << advection_steps << " (t = " << time << "): ";
    View<const Vector> x = fluid.position.read(MemorySpace::host);
    View<const Vector> v = fluid.velocity.read(MemorySpace::host);
    View<const T> rho = fluid.density.read(MemorySpace::host);
    View<const T> pr = fluid.pressure.read(MemorySpace::host);
    View<const std::uint64_t> id = fluid_body.particles().ids().read(MemorySpace::host);
    for (Index i = 0; i < fluid.size(); ++i) {  // owned particles (images are copies)
      // In the order an acoustic step computes them (density -> pressure -> velocity ->
      // position), so the variable named is the first that went wrong in this particle.
      const char* variable = nullptr;
      if (!std::isfinite(double(rho[i]))) variable = "Density (not finite)";
      else if (!std::isfinite(double(pr[i]))) variable = "Pressure (not finite)";
      for (int a = 0; a < D && !variable; ++a)
        if (!std::isfinite(double(v[i][a]))) variable = "Velocity (not finite)";
      for (int a = 0; a < D && !variable; ++a)
        if (!std::isfinite(double(x[i][a]))) variable = "Position (not finite)";
      if (!variable && !domain.contains(x[i])) variable = "Position (outside the domain)";
      if (variable) {
        s << "variable '" << variable << "' of fluid particle id " << id[i] << " (index " << i << "), at (";
        for (int a = 0; a < D; ++a) s << (a ? ", " : "") << double(x[i][a]);
        s << "), velocity (";
        for (int a = 0; a < D; ++a) s << (a ? ", " : "") << double(v[i][a]);
        s << ")";
        if (!share) throw SimulationError(s.str());
        // Several ranks: the lowest rank that found a particle names it; all stop.
        const comm::Communicator& c = share->comm();
        c.allreduce_max(std::uint64_t(1));
        c.check_all(false, s.str());
      }
    }
    if (share && share->comm().allreduce_max(std::uint64_t(0)) != 0) share->comm().check_all(true);
    s << what;
    fail(s.str());
  }

  void advance(double until) {
    visit_policy(policy, [&](auto p) {
      double speed = global_max(double(max_speed.exec(p)));
      if (!std::isfinite(speed)) diagnose("the largest speed is not finite");
      double advection_dt = criteria.advection_step(speed);
      if (!(advection_dt > 1e-9 * description.end_time)) {
        std::ostringstream s;
        s << "step " << advection_steps << " (t = " << time << "): the advection step " << advection_dt
          << " is below 1e-9 of the end time " << description.end_time << " (largest speed " << speed
          << ", fluid.viscosity " << description.viscosity << "): the run would not end";
        fail(s.str());
      }
      const double remaining_time = until - time;
      if (remaining_time <= 0) return;
      const bool ends_at_until = advection_dt >= remaining_time;
      if (ends_at_until) advection_dt = remaining_time;
      // Guards against a run that would never end its advection step: a sound speed out of
      // all proportion to the flow, or speeds that explode within the step (the acoustic step
      // shrinks with them while the advection step was fixed at its start).
      const double expected_steps = advection_dt / criteria.acoustic_step(speed);
      if (!(expected_steps < 1e6)) {
        std::ostringstream s;
        s << "step " << advection_steps << " (t = " << time << "): an advection step of " << advection_dt
          << " would take " << expected_steps << " acoustic steps of " << criteria.acoustic_step(speed)
          << " (fluid.sound_speed " << description.sound_speed << " against fluid.reference_velocity "
          << description.reference_velocity << " and the largest speed " << speed
          << "); weakly compressible SPH takes c0 about 10 U";
        fail(s.str());
      }
      std::uint64_t steps_here = 0;
      shift_particles(p);
      // The density from the kernel sum, or from the continuity equation alone (docs/sph.md, "Density").
      if (description.density_method != "continuity") density_summation.exec(p);
      if (fluid_images) fluid_images->refresh(p, fluid.density);  // prior acceleration reads rho_j
      if (share) share->refresh(p, fluid_body, *fluid_halo, ghost_density_name);
      update_kernel_correction(p);
      // Several ranks: the farthest a particle can have moved in this step (its shift included).
      double travelled = particle_shifting ? double(particle_shifting->largest_shift()) : 0.0;
      prior_acceleration.exec(p);
      // Each acoustic step: pressure start (rho, p, x), pressure relaxation (a), velocity
      // update (v, x) with the largest speed, density relaxation (drho/dt), density update
      // (rho). The density update of a step and the start of the next run as one launch, as
      // do the velocity update and the speed reduction (fused_updates.hpp); the values are
      // those of the separate kernels, and what a diagnosis or a limit sees is the state
      // after a whole step, as before.
      const auto too_many_steps = [&] { return double(++steps_here) > 100 * expected_steps + 1000; };
      const auto blew_up = [&] {
        std::ostringstream s;
        s << "the largest speed grew to " << speed << " within one advection step (acoustic step " << last_acoustic_dt
          << ", " << steps_here << " of them): the flow blew up";
        diagnose(s.str());
      };
      double relaxed = 0;
      // Where the time goes (the device waited for at each mark; on one rank too, to compare).
      const auto loop_start = RankShare<T, D>::now(p);
      const double refreshed_before_loop = share ? share->timings().refresh_seconds : 0.0;
      // The last step is shortened to end at Dt, or kept whole where the case asks for it
      // (time.last_acoustic_step); never past `until`, and never longer than a Dt that the
      // viscous limit made shorter than one acoustic step.
      const bool shorten_last = description.last_acoustic_step != "full" || ends_at_until;
      const auto next_acoustic_step = [&] {
        double dt = criteria.acoustic_step(speed);
        const double left = advection_dt - relaxed;
        if (dt >= left && (shorten_last || relaxed == 0)) dt = left;
        if (dt >= remaining_time - relaxed) dt = remaining_time - relaxed;
        return dt;
      };
      // advection_dt > 0 (checked above): at least one acoustic step.
      if (too_many_steps()) blew_up();
      double dt = next_acoustic_step();
      last_acoustic_dt = dt;
      pressure_start.exec(p, Real(dt));
      for (;;) {
        place_walls(p, time + relaxed + 0.5 * dt);  // moving walls at the acoustic step's middle
        if (wall_pressure_average) wall_pressure_average->exec(p);  // from this step's pressures
        with_current_records(
            p, [&] { relax_pressure(p, Real(dt)); },
            [&](View<const std::uint32_t> items, bool interior) { relax_pressure(p, Real(dt), items, interior); });
        sample_loads(p, dt);
        const double speed_before = speed;
        speed = global_max(double(velocity_update_and_max_speed.exec(p, Real(dt))));
        if (share) {
          travelled += dt * std::max(speed_before, speed);
          if (travelled > double(share->travel_limit())) {
            std::ostringstream s;
            s << "step " << advection_steps << " (t = " << time << "): a particle may have moved " << travelled
              << " within one advection step, more than half the halo's skin (" << double(share->travel_limit())
              << "): the flow accelerated too fast for the run on several ranks";
            fail(s.str());
          }
        }
        if (damping_rate > 0) velocity_damping.exec(p, Real(std::exp(-damping_rate * dt)));
        if (damping_zone) damping_zone->exec(p, Real(dt));  // [damping_zone]: wave absorption
        with_current_records(
            p, [&] { density_relaxation.exec(p, Real(dt)); },
            [&](View<const std::uint32_t> items, bool interior) {
              exec_listed(density_relaxation, p, items, Real(dt), interior);
            });
        relaxed += dt;
        ++acoustic_steps;
        const bool more = advection_dt - relaxed > 1e-12 * advection_dt;  // a full last step passes Dt
        if (!std::isfinite(speed) || !more || too_many_steps()) {
          density_update.exec(p, Real(dt));
          if (!std::isfinite(speed)) diagnose("the largest speed is not finite");
          if (more) blew_up();
          break;
        }
        const double next = next_acoustic_step();
        density_update_and_start.exec(p, Real(dt), Real(next));
        dt = next;
        last_acoustic_dt = dt;
      }
      const auto loop_end = RankShare<T, D>::now(p);
      acoustic_loop_seconds += RankShare<T, D>::seconds(loop_start, loop_end);
      if (share) {
        share->settle_timings();
        acoustic_refresh_seconds += share->timings().refresh_seconds - refreshed_before_loop;
      }
      time += relaxed;
      ++advection_steps;
      finish_loads();
      const bool sort_now = advection_steps % std::uint64_t(description.sort_every) == 0;
      // Several ranks: the domain cut anew where the fluid counts drifted apart.
      bool rebalanced = false;
      if (share && share->unbalanced(fluid.size())) {
        share->decompose(fluid_body);
        share->count_rebalance();
        rebalanced = true;
      }
      const bool walls_move = move_walls && !walls_held;
      if (walls_move) place_walls(p, time);  // moving walls at the step's end
      if (share && (walls_move || rebalanced)) {
        redistribute_walls(p, true);
      } else if (walls_move && !wall_cells.keep_if_cells_unchanged(p)) {
        // Sorted with the fluid and binned again where a wall particle changed its cell; while
        // none does, the walls keep their (cell, id) order and their lists, which a sort and a
        // build would give again.
        if (sort_now) wall_sorter.sort(p);
        wall_cells.build(p);
      }
      if (fluid_images) fluid_images->wrap(p);  // before the sort: its cells are the box's
      if (rank_wrap) rank_wrap->wrap(p);        // before the migration: owners by the wrapped position
      if (share) share->migrate(p, fluid_body);  // before the sort: the arrivals are sorted with the rest
      const auto before_sort = RankShare<T, D>::now(p);
      if (sort_now) fluid_sorter.sort(p);
      const auto sorted = RankShare<T, D>::now(p);
      sort_seconds += RankShare<T, D>::seconds(before_sort, sorted);
      if (share) {
        share->gather(p, fluid_body, fluid_halo);
        fluid_ghost_sum += double(fluid_halo->ghost_count());
        ++fluid_ghost_samples;
      }
      const auto before_rebuild = RankShare<T, D>::now(p);
      rebuild(p);
      const auto rebuilt = RankShare<T, D>::now(p);
      rebuild_seconds += RankShare<T, D>::seconds(before_rebuild, rebuilt);
      step_end_seconds += RankShare<T, D>::seconds(loop_end, rebuilt);
    });
  }

  static constexpr const char* precision_name = sizeof(T) == 4 ? "float" : "double";

  // On several ranks every rank calls it: rank 0 gathers each body's owned particles (in rank
  // order) and writes the one file, the same format as a run on one rank's, which a run on any
  // number of ranks restores; a failure to write stops every rank with rank 0's line.
  void write_checkpoint(const std::filesystem::path& path, const std::string& run_state) {
    io::CheckpointWriter out(solver_checkpoint_version);
    out.section("run");
    out.u32(D);
    out.u32(sizeof(T));
    out.string(precision_name);
    write_case(out, description);
    out.section("time");
    out.f64(time);
    out.u64(advection_steps);
    out.u64(acoustic_steps);
    out.u32(0);  // phase: between advection steps (solver_checkpoint.hpp)
    out.u64(removed_particles);
    out.f64(removed_mass);
    if (share) {
      const bool lead = share->comm().rank() == 0;
      write_gathered_body(lead ? &out : nullptr, fluid_body);
      write_gathered_body(lead ? &out : nullptr, wall_body);
      out.section("observers");
      out.string(run_state);
      std::string error;
      if (lead) {
        try {
          out.commit(path);
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
      share->comm().check_all(error.empty(), error);
      return;
    }
    write_body(out, fluid_body);
    write_body(out, wall_body);
    out.section("observers");
    out.string(run_state);
    out.commit(path);
  }

  // Several ranks: a body as write_body writes it, its owned particles gathered from every rank
  // to rank 0 (`out` there, null elsewhere), in rank order. Collective.
  void write_gathered_body(io::CheckpointWriter* out, Body<T, D>& body) {
    const comm::Communicator& c = share->comm();
    ParticleSet& set = body.particles();
    const Index owned = set.owned_count();
    const std::vector<std::uint64_t> counts = c.allgather(std::uint64_t(owned));
    std::uint64_t total = 0;
    for (std::uint64_t n : counts) total += n;
    if (out) {
      out->section("body");
      out->string(body.name());
      out->u64(total);
      out->u64(set.first_id());
      out->u64(set.variables().sortable_names().size());
    }
    std::vector<char> gathered;
    set.variables().for_each([&](VariableRegistry::Entry& e) {
      if (!e.flags.sortable) return;
      VariableBase& v = *e.variable;
      const std::size_t element = v.element_size();
      std::vector<comm::Communicator::Segment> send(std::size_t(c.size()), {nullptr, 0});
      std::vector<comm::Communicator::Segment> recv(std::size_t(c.size()), {nullptr, 0});
      send[0] = {const_cast<void*>(v.prepare(MemorySpace::host, Access::read)), owned * element};
      if (out) {
        gathered.resize(total * element);
        std::size_t at = 0;
        for (int r = 0; r < c.size(); ++r) {
          recv[std::size_t(r)] = {gathered.data() + at, counts[std::size_t(r)] * element};
          at += counts[std::size_t(r)] * element;
        }
      }
      c.exchange(send, recv);
      if (out) {
        out->string(v.name());
        out->string(e.type_name);
        out->u64(element);
        out->block(gathered.data(), total * element);
      }
    });
  }

  static void write_body(io::CheckpointWriter& out, Body<T, D>& body) {
    ParticleSet& set = body.particles();
    out.section("body");
    out.string(body.name());
    out.u64(set.owned_count());
    out.u64(set.first_id());
    out.u64(set.variables().sortable_names().size());
    set.variables().for_each([&](VariableRegistry::Entry& e) {
      if (!e.flags.sortable) return;
      VariableBase& v = *e.variable;
      out.string(v.name());
      out.string(e.type_name);
      out.u64(v.element_size());
      out.block(v.prepare(MemorySpace::host, Access::read), set.owned_count() * v.element_size());
    });
  }

  // The contents of one body, read and checked in full before any variable is overwritten.
  struct StagedBody {
    Index owned = 0;
    std::vector<std::pair<VariableBase*, std::string>> variables;
  };
  static StagedBody read_body(io::CheckpointReader& in, Body<T, D>& body) {
    ParticleSet& set = body.particles();
    in.section("body");
    const std::string name = in.string();
    if (name != body.name()) in.fail("holds body '" + name + "' where '" + body.name() + "' was expected");
    const std::uint64_t owned = in.u64();
    // Fluid particles may have left the domain since the start: fewer, never more.
    const std::uint64_t made = set.id_count();
    if (owned > made || (owned != made && name != "Water"))
      in.fail("holds " + std::to_string(owned) + " particles of '" + name + "'; this case has " + std::to_string(made));
    if (in.u64() != set.first_id()) in.fail("holds other particle ids for '" + name + "'");
    const std::uint64_t count = in.u64();
    const std::size_t sortable = set.variables().sortable_names().size();
    StagedBody staged;
    staged.owned = Index(owned);
    for (std::uint64_t k = 0; k < count; ++k) {
      const std::string variable = in.string();
      const std::string type = in.string();
      const std::uint64_t element = in.u64();
      VariableRegistry::Entry* entry = nullptr;
      bool derived = false;  // a variable this solver recomputes before reading it
      set.variables().for_each([&](VariableRegistry::Entry& e) {
        if (e.variable->name() != variable) return;
        if (e.flags.sortable) entry = &e;
        else derived = true;
      });
      if (derived) {
        // A checkpoint of an earlier build, which kept the accelerations (fluid_variables.hpp).
        std::string skipped(owned * element, '\0');
        in.block(skipped.data(), skipped.size(), "'" + name + "." + variable + "'");
        continue;
      }
      if (!entry) in.fail("holds variable '" + variable + "' of '" + name + "', which this solver does not have");
      if (type != entry->type_name || element != entry->variable->element_size())
        in.fail("holds '" + name + "." + variable + "' as " + type + "; this solver has " + entry->type_name);
      std::string bytes(owned * element, '\0');
      in.block(bytes.data(), bytes.size(), "'" + name + "." + variable + "'");
      staged.variables.emplace_back(entry->variable.get(), std::move(bytes));
    }
    if (staged.variables.size() != sortable)
      in.fail("holds " + std::to_string(staged.variables.size()) + " of the " + std::to_string(sortable) +
              " variables of '" + name + "' this solver keeps");
    return staged;
  }
  // The set takes the checkpoint's particles, as many as it holds: fewer than a fresh set's
  // (fluid that left the domain), or more than this rank's share on several ranks (the set is
  // made whole again; the caller keeps this rank's share). The set has no ghosts.
  static void commit(Body<T, D>& body, const StagedBody& staged) {
    ParticleSet& set = body.particles();
    set.variables().resize(staged.owned);
    for (const auto& [variable, bytes] : staged.variables)
      if (!bytes.empty()) std::memcpy(variable->prepare(MemorySpace::host, Access::write), bytes.data(), bytes.size());
    set.adopt_owned(seq, staged.owned);  // owned count, and index_of_id() from the restored ids
  }

  // On several ranks every rank calls it and reads the whole file (a checkpoint of any number
  // of ranks); a bad file stops every rank with one line; the domain is then cut anew from the
  // restored positions and each rank keeps its share.
  std::string restore_checkpoint(const std::filesystem::path& path) {
    if (!share) return restore_whole(path);
    std::string run_state, error;
    try {
      run_state = restore_whole(path);
    } catch (const std::exception& e) {
      error = e.what();
    }
    share->comm().check_all(error.empty(), error);
    return run_state;
  }

  std::string restore_whole(const std::filesystem::path& path) {
    io::CheckpointReader in(path, solver_checkpoint_version);
    in.section("run");
    const std::uint32_t dimension = in.u32();
    const std::uint32_t bytes = in.u32();
    const std::string precision = in.string();
    if (dimension != std::uint32_t(D) || bytes != sizeof(T))
      in.fail("holds a " + std::to_string(dimension) + "D " + precision + " run; it cannot continue as a " +
              std::to_string(D) + "D " + precision_name + " run");
    const CaseDescription saved = read_case(in);
    if (const std::string difference = physics_difference(description, saved); !difference.empty())
      in.fail("was written for another case ('" + saved.name + "'): " + difference);
    in.section("time");
    const double saved_time = in.f64();
    const std::uint64_t saved_advection = in.u64();
    const std::uint64_t saved_acoustic = in.u64();
    if (const std::uint32_t phase = in.u32(); phase != 0)
      in.fail("was taken in phase " + std::to_string(phase) + " of an advection step; this solver knows phase 0");
    const std::uint64_t saved_removed = in.u64();
    const double saved_removed_mass = in.f64();
    const StagedBody staged_fluid = read_body(in, fluid_body);
    const StagedBody staged_wall = read_body(in, wall_body);
    in.section("observers");
    std::string run_state = in.string();
    if (!in.at_end()) in.fail("has unread bytes after its last section");

    // Images are not stored: the sets lose theirs (shrink_owned needs a set without ghosts) and
    // rebuild them below.
    for (Body<T, D>* body : {&fluid_body, &wall_body})
      if (body->particles().ghost_count() != 0) body->particles().set_ghost_count(0);
    commit(fluid_body, staged_fluid);
    commit(wall_body, staged_wall);
    time = saved_time;
    advection_steps = saved_advection;
    acoustic_steps = saved_acoustic;
    removed_particles = Index(saved_removed);
    removed_mass = saved_removed_mass;
    last_acoustic_dt = 0;
    visit_policy(policy, [&](auto p) {
      if (share) {
        // The restored sets are whole on every rank: cut the domain anew and keep each share,
        // as at the start.
        take_shares(p);
        return;
      }
      // As at the end of an advection step: neighbour structures from the restored order.
      // Walls that do not move are never sorted again: sorted here (by cell and id, so that a
      // checkpoint of one rank keeps its order, and one of several ranks, written in rank
      // order, gets back the in-cell-order search).
      if (!move_walls) wall_sorter.sort(p);
      build_wall(p);
      rebuild(p);
    });
    return run_state;
  }

  PairCounts count_pairs() {
    PairCounts c;
    visit_policy(policy, [&](auto p) {
      const Index n = fluid.size();
      for (const NeighborSearch<T, D>& s : {inner.direct_search(p), contact.direct_search(p)}) {
        c.candidate_pairs += particle_reduce(p, n, Sum<std::uint64_t>{}, CandidateCount<T, D>{s});
        c.neighbor_pairs += particle_reduce(p, n, Sum<std::uint64_t>{}, NeighborCount<T, D>{s});
      }
    });
    return c;
  }

  void pressure_relaxation_pass() {
    const double dt = last_acoustic_dt > 0 ? last_acoustic_dt : criteria.acoustic_step(0);
    visit_policy(policy, [&](auto p) {
      update_kernel_correction(p);
      if (wall_pressure_average) wall_pressure_average->exec(p);
      relax_pressure(p, Real(dt));
      fence(p);
    });
  }
  // The momentum equation's pair sums, with the kernel gradient corrected where the case asks.
  template <class P>
  void relax_pressure(P p, Real dt) {
    if (corrected_pressure_relaxation)
      corrected_pressure_relaxation->exec(p, dt);
    else
      pressure_relaxation.exec(p, dt);
  }
  template <class P>
  void relax_pressure(P p, Real dt, View<const std::uint32_t> items, bool interior) {
    if (corrected_pressure_relaxation)
      exec_listed(*corrected_pressure_relaxation, p, items, dt, interior);
    else
      exec_listed(pressure_relaxation, p, items, dt, interior);
  }
  // A pass over listed fluid particles. The interior ones (InteriorSplit) have owned neighbours
  // only: where both cell lists give the owned particles' view in cell order
  // (CellLinkedList::owned_view), their pass searches that view and runs the kernel's one-rank
  // common case, the same neighbours in the same order as through the id-ordered lists' runs
  // (rebuild() then splits with the finer reach, which needs a search that visits no ghost).
  template <class Dynamics, class P>
  void exec_listed(Dynamics& dynamics, P p, View<const std::uint32_t> items, Real dt, bool interior) {
    if (interior && fluid_cells.owned_view_ready() && wall_cells.owned_view_ready()) {
      const CellListView<T, D> fluid_view = fluid_cells.owned_view(p), wall_view = wall_cells.owned_view(p);
      dynamics.exec_items_with(p, items, dt, [&](auto& kernel) {
        kernel.inner.targets = fluid_view;
        kernel.contact.targets = wall_view;
      });
    } else {
      dynamics.exec_items(p, items, dt);
    }
  }
  // A relaxation pass (`all()`, or `some(items, interior)` over listed particles) after the
  // images' and ghosts' neighbour records are made current. Where the refreshes overlap, the
  // interior particles' part runs while the ghosts' records travel and the border particles'
  // after them (on the device beside the interior part: RankShare::refresh_end): each
  // particle's sums are those of the whole pass (the same bits).
  template <class P, class All, class Some>
  void with_current_records(P p, All&& all, Some&& some) {
    if (fluid_images) refresh_image_records(p);
    if (!overlap_refreshes) {
      if (share) refresh_ghost_records(p);
      all();
      return;
    }
    share->refresh_begin(p, fluid_body, *fluid_halo, ghost_record_names);
    some(fluid_split.interior(p), true);
    share->refresh_end(p, fluid_body, *fluid_halo, [&] {
      shift_ghost_image_records(p);
      some(fluid_split.border(p), false);
    });
  }
  // fluid.particle_shifting: every fluid particle moved back towards an even arrangement
  // (particle_shifting.hpp), at the start of the advection step, before the density is summed.
  // The kernel sums and the shifts read the neighbours' records, current at the step's start (the
  // last rebuild refreshed the owned particles', the images' and the ghosts'); the shifts read the
  // neighbours' kernel sums, images' and ghosts' too. After the move the owned particles', the
  // images' and the ghosts' records and positions follow it.
  template <class P>
  void shift_particles(P p) {
    if (!particle_shifting) return;
    shifting_kernel_sums->exec(p);
    if (fluid_images) fluid_images->refresh(p, *shifting_kernel_sum);
    if (share) share->refresh(p, fluid_body, *fluid_halo, shifting_kernel_sum_name);
    particle_shifting->exec(p);
    particle_for(p, fluid.size(),
                 ApplyParticleShift<T, D>{fluid.position.read_write(p), particle_shifting->shifts().read(p)});
    refresh_records.exec(p);
    if (fluid_images) refresh_image_records(p);
    if (share) refresh_ghost_records(p);
    // Stored lists keep each pair's geometry from their update, before the shift: the step's
    // relaxations would see that arrangement while its summation sees the shifted one (on the
    // Taylor-Green vortex the kinetic energy then jumped by up to 5 times between samples; docs/sph.md,
    // "Periodic axes", session 25). The pairs are found and measured anew from the shifted
    // positions, through the cells of the step's start (a shift is at most 0.1 h).
    if (inner.method(p) == SearchMethod::stored) inner.update(p, PairKernelDerivative<T, D>{kernel});
    if (contact.method(p) == SearchMethod::stored) contact.update(p, PairKernelDerivative<T, D>{kernel});
  }

  // B of every owned fluid particle from the step's positions, then of the images and ghosts
  // (their own neighbourhoods are cut off by the halo: they take their source's).
  template <class P>
  void update_kernel_correction(P p) {
    if (!kernel_correction_matrices) return;
    kernel_correction_matrices->exec(p);
    if (fluid_images) fluid_images->refresh(p, *kernel_correction);
    if (share) share->refresh(p, fluid_body, *fluid_halo, kernel_correction_name);
  }

  ObserverSample observe() {
    ObserverSample s;
    s.time = time;
    visit_policy(policy, [&](auto p) {
      // A probe near a periodic face reads the images across it.
      if (!share && fluid_images && observers.probe_count() > 0)
        fluid_images->refresh(p, fluid.pressure, fluid.density, fluid.mass);
      const typename FluidObservers<T, D>::Sample o = observers.exec(p);
      s.front = double(o.front);
      s.kinetic_energy = double(o.energy[0]);
      s.potential_energy = double(o.energy[1]);
      s.mass = double(o.mass);
      if (share) {
        // Each rank's owned particles; the sums folded in rank order (comm::Communicator).
        s.front = share->comm().allreduce_max(s.front);
        s.kinetic_energy = global_sum(s.kinetic_energy);
        s.potential_energy = global_sum(s.potential_energy);
        s.mass = global_sum(s.mass);
        // A pressure probe's kernel may reach beyond the halo (probe.kernel_width): each rank
        // sums over its owned particles, and the sums are added.
        for (const Vec<T, 2>& sums : o.probe_sums) {
          const double weighted = global_sum(double(sums[0])), weight = global_sum(double(sums[1]));
          s.probe_pressure.push_back(weight > 0 ? weighted / weight : 0.0);
        }
      } else {
        for (const Vec<T, 2>& sums : o.probe_sums)
          s.probe_pressure.push_back(sums[1] > T(0) ? double(sums[0] / sums[1]) : 0.0);
      }
      // Gauges and velocity probes (the fluid's kernel, within the halo's reach): on several
      // ranks each point is read by the rank that owns it, from its owned particles and ghosts
      // (every particle within the cutoff of its cells, after the step's halo, in the cells'
      // order by id, as the relaxations see them), and the readings are combined
      // (comm::Communicator::combine_owned): the bits of one rank.
      if (velocity_probes) {
        std::vector<VelocityProbeSums<T, D>> sums = velocity_probes->sums(p);
        if (share) {
          constexpr std::size_t width = 2 * D + 1;
          std::vector<double> flat(sums.size() * width, 0.0);
          for (std::size_t k = 0; k < sums.size(); ++k) {
            if (!owns(velocity_probes->probes()[k].position)) continue;
            for (int a = 0; a < D; ++a) {
              flat[k * width + std::size_t(a)] = double(sums[k].reference[a]);
              flat[k * width + D + std::size_t(a)] = double(sums[k].weighted[a]);
            }
            flat[k * width + 2 * D] = double(sums[k].weight);
          }
          combine_owned(flat);
          for (std::size_t k = 0; k < sums.size(); ++k) {
            for (int a = 0; a < D; ++a) {
              sums[k].reference[a] = T(flat[k * width + std::size_t(a)]);
              sums[k].weighted[a] = T(flat[k * width + D + std::size_t(a)]);
            }
            sums[k].weight = T(flat[k * width + 2 * D]);
          }
        }
        for (const VelocityReading<T, D>& r : VelocityProbes<T, D>::readings(sums))
          for (int a = 0; a < D; ++a) s.probe_velocity.push_back(double(r.velocity[a]));
      }
      if (gauges) {
        std::vector<T> sums = gauges->sums(p);
        if (share) {
          std::vector<double> owned_sums(sums.size(), 0.0);
          for (std::size_t k = 0; k < sums.size(); ++k)
            if (owns(gauges->sample_points()[k])) owned_sums[k] = double(sums[k]);
          combine_owned(owned_sums);
          for (std::size_t k = 0; k < sums.size(); ++k) sums[k] = T(owned_sums[k]);
        }
        for (const GaugeReading<T>& r : gauges->readings(sums)) s.gauge_elevation.push_back(double(r.elevation));
      }
    });
    return s;
  }
  // Several ranks: whether this rank owns the point (one rank: always).
  bool owns(const Vector& x) const { return !share || share->owns(x); }
  void combine_owned(std::vector<double>& values) const {
    if (share) share->comm().combine_owned(values);
  }

  // Before every other member: the set-up's wall time counts from here (making_seconds).
  std::chrono::steady_clock::time_point constructed_from = std::chrono::steady_clock::now();
  CaseDescription description;
  PolicyKind policy;
  WendlandC2Kernel<T, D> kernel;
  // The set-up's wall time: making the particles and the solver's structures (host; on several
  // ranks the transport's start and a share's cut too), then placing them (their variables
  // filled; on several ranks the cut of a case made whole, the shares, sorts and halos).
  double making_seconds = 0, placing_seconds = 0;
  // A case made in shares (made_in_shares): the cut its particles were made for, until the
  // rank share adopts it.
  std::optional<comm::Decomposition<D>> initial_cut;
  TankParticles<T, D> particles;
  std::vector<WallBodyCount> wall_groups;  // each wall body's particles, in the order of their ids
  std::vector<Index> obstacle_counts;  // wall particles of each obstacle (after the tank's)
  Index removed_fluid = 0;             // lattice points the obstacles took
  // Moving walls (moving_walls.hpp; all null / empty when every wall is at rest).
  std::unique_ptr<WallMotionVariables<T, D>> wall_motion;
  DiscreteVariable<StoredRigidMotion<D>> motions{"WallMotions"};
  std::vector<std::unique_ptr<MotionTable>> motion_tables;
  std::unique_ptr<MoveWalls<T, D>> move_walls;
  std::unique_ptr<ParticleShifting<T, D>> particle_shifting;  // fluid.particle_shifting > 0
  std::unique_ptr<ShiftingKernelSum<T, D>> shifting_kernel_sums;  // its first pass
  DiscreteVariable<T>* shifting_kernel_sum = nullptr;             // C_i / the lattice's, ghosts and images too
  const std::vector<std::string> shifting_kernel_sum_name{"ShiftingKernelSum"};
  bool walls_held = false;  // through the settling stage
  // report.loads: the wall loads, their dt-weighted sum over the acoustic steps of the current
  // advection step, and the mean over the last one.
  std::unique_ptr<WallLoad<T, D>> wall_load;
  std::unique_ptr<WaveGauges<T, D>> gauges;  // [[gauge]]
  std::unique_ptr<VelocityProbes<T, D>> velocity_probes;  // [[velocity_probe]]
  std::unique_ptr<DampingZone<T, D>> damping_zone;          // [damping_zone]
  std::vector<WallBodyLoad<double, D>> load_sum;
  std::vector<WallLoadSample> step_loads;
  double load_time = 0;
  // Each fluid particle's initial velocity by id, kept through the settling stage (empty: all zero).
  std::vector<Vector> initial_velocity;
  std::vector<RelaxedBodyReport> relaxed;  // the bodies made with fill = "relaxed"
  Box<T, D> domain;
  Body<T, D> fluid_body;
  Body<T, D> wall_body;
  FluidVariables<T, D> fluid;
  WallVariables<T, D> wall;
  // Ghost images along periodic axes (case domain.periodic); null where no axis is periodic.
  std::unique_ptr<PeriodicImages<T, D>> fluid_images;
  std::unique_ptr<PeriodicImages<T, D>> wall_images;
  // Several ranks with periodic axes: the fluid's images object, kept to wrap positions into the
  // box (the halo makes the images); fluid_images and wall_images are then null.
  std::unique_ptr<PeriodicImages<T, D>> rank_wrap;
  Box<T, D> search_box;  // of the cell lists: beyond the periodic faces, or around the particles (search_box_of)
  CellLinkedList<T, D> fluid_cells;
  CellLinkedList<T, D> wall_cells;
  InnerRelation<T, D> inner;
  ContactRelation<T, D> contact;
  ParticleSorter<T, D> fluid_sorter;
  ParticleSorter<T, D> wall_sorter;
  WeaklyCompressibleEquationOfState<T> eos;
  AcousticRiemannSolver<T> riemann;
  T wall_volume;
  TimeStepCriteria criteria;
  DensitySummationFreeSurface<T, D> density_summation;
  PriorAcceleration<T, D> prior_acceleration;
  PressureRelaxationStart<T, D> pressure_start;
  std::unique_ptr<WallPressureAverage<T, D>> wall_pressure_average;  // fluid.wall_pressure = "averaged"
  WallFreeBox<T, D> wall_free;  // of the tank: fluid particles there have no wall neighbour
  PressureRelaxation<T, D> pressure_relaxation;
  // fluid.kernel_gradient_correction: each fluid particle's B (ghosts and images included), the
  // pass that computes it once per advection step, and the corrected momentum equation.
  DiscreteVariable<Mat<T, D>>* kernel_correction = nullptr;
  std::unique_ptr<KernelCorrectionMatrices<T, D>> kernel_correction_matrices;
  std::unique_ptr<CorrectedPressureRelaxation<T, D>> corrected_pressure_relaxation;
  const std::vector<std::string> kernel_correction_name{"KernelCorrection"};
  VelocityUpdate<T, D> velocity_update;
  DensityRelaxation<T, D> density_relaxation;
  DensityUpdate<T, D> density_update;
  MaximumSpeed<T, D> max_speed;
  VelocityUpdateAndMaxSpeed<T, D> velocity_update_and_max_speed;
  VelocityDamping<T, D> velocity_damping;
  DensityUpdateAndPressureStart<T, D> density_update_and_start;
  RefreshNeighborRecords<T, D> refresh_records;
  FluidObservers<T, D> observers;  // front, energies, mass, pressure probes: one pass
  double time = 0;
  std::uint64_t advection_steps = 0;
  std::uint64_t acoustic_steps = 0;
  double last_acoustic_dt = 0;  // for pressure_relaxation_pass()
  double damping_rate = 0;      // 1/time, while settling
  Index removed_particles = 0;  // fluid particles that left the domain (domain.leaving = "remove")
  double removed_mass = 0;
  SettlingReport settling;
  // Several ranks (null on one): the decomposition, transport and halos (rank_share.hpp).
  std::unique_ptr<RankShare<T, D>> share;
  std::unique_ptr<typename RankShare<T, D>::Halo> fluid_halo;
  std::unique_ptr<typename RankShare<T, D>::Halo> wall_halo;
  // Several ranks, where the refreshes within the acoustic steps overlap the interior particles'
  // relaxations (RankShare::overlap_refreshes): the owned fluid split after each halo build.
  bool overlap_refreshes = false;
  comm::InteriorSplit<D> fluid_split;
  // Wall time in the acoustic steps of advance() (ghost refreshes included) and in the ends of
  // its advection steps (migration, sort, halo, neighbour structures), on any number of ranks.
  double acoustic_loop_seconds = 0;
  double acoustic_refresh_seconds = 0;  // the ghost refreshes within the acoustic steps
  double step_end_seconds = 0;
  double speed_wait_seconds = 0;  // several ranks: in the largest speed's reductions (global_max)
  double sort_seconds = 0;        // of the step ends: the fluid's sort
  double rebuild_seconds = 0;     //   the cell lists, neighbour structures and records (rebuild)
  double fluid_ghost_sum = 0;  // fluid ghosts after each advection step's halo, summed
  std::uint64_t fluid_ghost_samples = 0;
  // What the ghosts' refreshes send: before each relaxation, and after the density summation.
  const std::vector<std::string> ghost_record_names{fluid.position.name(), fluid.neighbor_position_volume.name(),
                                                    fluid.neighbor_velocity_pressure.name()};
  const std::vector<std::string> ghost_density_name{fluid.density.name()};
};

template <class T, int D>
WeaklyCompressibleSolver<T, D>::WeaklyCompressibleSolver(const CaseDescription& description, PolicyKind policy,
                                                         bool settle)
    : state_(std::make_unique<State>(description, policy, settle, nullptr)) {}
template <class T, int D>
WeaklyCompressibleSolver<T, D>::WeaklyCompressibleSolver(const CaseDescription& description, PolicyKind policy,
                                                         const comm::Communicator& comm, bool settle)
    : state_(std::make_unique<State>(description, policy, settle, &comm)) {}
template <class T, int D>
WeaklyCompressibleSolver<T, D>::~WeaklyCompressibleSolver() = default;
template <class T, int D>
void WeaklyCompressibleSolver<T, D>::advance(double until) { state_->advance(until); }
template <class T, int D>
ObserverSample WeaklyCompressibleSolver<T, D>::observe() { return state_->observe(); }
template <class T, int D>
double WeaklyCompressibleSolver<T, D>::time() const { return state_->time; }
template <class T, int D>
std::uint64_t WeaklyCompressibleSolver<T, D>::advection_steps() const { return state_->advection_steps; }
template <class T, int D>
std::uint64_t WeaklyCompressibleSolver<T, D>::acoustic_steps() const { return state_->acoustic_steps; }
template <class T, int D>
const SettlingReport& WeaklyCompressibleSolver<T, D>::settling() const { return state_->settling; }
template <class T, int D>
Index WeaklyCompressibleSolver<T, D>::fluid_count() const { return state_->fluid.size(); }
template <class T, int D>
std::uint64_t WeaklyCompressibleSolver<T, D>::fluid_count_all_ranks() const {
  return state_->global_sum(std::uint64_t(state_->fluid.size()));
}
template <class T, int D>
std::uint64_t WeaklyCompressibleSolver<T, D>::particles_migrated() const {
  return state_->share ? state_->share->migrated() : 0;
}
template <class T, int D>
std::string WeaklyCompressibleSolver<T, D>::transport() const {
  return state_->share ? std::string(state_->share->transport().name()) : std::string();
}
template <class T, int D>
typename WeaklyCompressibleSolver<T, D>::RankTimings WeaklyCompressibleSolver<T, D>::rank_timings() const {
  RankTimings r;
  if (state_->share) {
    const auto& t = state_->share->timings();
    r.plan_seconds = t.plan_seconds;
    r.migration_plan_seconds = t.migration_plan_seconds;
    r.exchange_seconds = t.exchange_seconds;
    r.migrate_seconds = t.migrate_seconds;
    r.gather_seconds = t.gather_seconds;
    r.refresh_seconds = t.refresh_seconds;
    r.exchanges = t.exchanges;
  }
  r.acoustic_loop_seconds = state_->acoustic_loop_seconds;
  r.acoustic_refresh_seconds = state_->acoustic_refresh_seconds;
  r.step_end_seconds = state_->step_end_seconds;
  r.speed_wait_seconds = state_->speed_wait_seconds;
  r.sort_seconds = state_->sort_seconds;
  r.rebuild_seconds = state_->rebuild_seconds;
  return r;
}
template <class T, int D>
typename WeaklyCompressibleSolver<T, D>::RankBalance WeaklyCompressibleSolver<T, D>::rank_balance() const {
  if (!state_->share) return {};
  const auto b = state_->share->balance();
  RankBalance r;
  r.method = comm::to_string(state_->share->method());
  r.mean_imbalance = b.mean_imbalance;
  r.worst_imbalance = b.worst_imbalance;
  r.mean_fluid_ghosts =
      state_->fluid_ghost_samples ? state_->fluid_ghost_sum / double(state_->fluid_ghost_samples) : 0.0;
  return r;
}
template <class T, int D>
std::uint64_t WeaklyCompressibleSolver<T, D>::rebalances() const {
  return state_->share ? state_->share->rebalances() : 0;
}
template <class T, int D>
std::pair<double, double> WeaklyCompressibleSolver<T, D>::setup_seconds() const {
  return {state_->making_seconds, state_->placing_seconds};
}
template <class T, int D>
bool WeaklyCompressibleSolver<T, D>::made_in_shares() const {
  return state_->share && State::made_in_shares(state_->description, &state_->share->comm());
}
template <class T, int D>
Index WeaklyCompressibleSolver<T, D>::wall_count() const { return state_->wall.size(); }
template <class T, int D>
const std::vector<Index>& WeaklyCompressibleSolver<T, D>::obstacle_wall_counts() const { return state_->obstacle_counts; }
template <class T, int D>
Index WeaklyCompressibleSolver<T, D>::removed_fluid_count() const { return state_->removed_fluid; }
template <class T, int D>
const std::vector<WallBodyCount>& WeaklyCompressibleSolver<T, D>::wall_bodies() const { return state_->wall_groups; }
template <class T, int D>
const std::vector<RelaxedBodyReport>& WeaklyCompressibleSolver<T, D>::relaxed_bodies() const { return state_->relaxed; }
template <class T, int D>
const std::vector<WallLoadSample>& WeaklyCompressibleSolver<T, D>::loads() const { return state_->step_loads; }
template <class T, int D>
Index WeaklyCompressibleSolver<T, D>::left_domain_count() const { return state_->removed_particles; }
template <class T, int D>
double WeaklyCompressibleSolver<T, D>::left_domain_mass() const { return state_->removed_mass; }
template <class T, int D>
double WeaklyCompressibleSolver<T, D>::smoothing_length() const { return double(state_->kernel.h); }
template <class T, int D>
PolicyKind WeaklyCompressibleSolver<T, D>::policy() const { return state_->policy; }
template <class T, int D>
const CaseDescription& WeaklyCompressibleSolver<T, D>::description() const { return state_->description; }
template <class T, int D>
Body<T, D>& WeaklyCompressibleSolver<T, D>::fluid_body() { return state_->fluid_body; }
template <class T, int D>
Body<T, D>& WeaklyCompressibleSolver<T, D>::wall_body() { return state_->wall_body; }
template <class T, int D>
void WeaklyCompressibleSolver<T, D>::write_checkpoint(const std::filesystem::path& path, const std::string& run_state) {
  state_->write_checkpoint(path, run_state);
}
template <class T, int D>
std::string WeaklyCompressibleSolver<T, D>::restore_checkpoint(const std::filesystem::path& path) {
  return state_->restore_checkpoint(path);
}
template <class T, int D>
PairCounts WeaklyCompressibleSolver<T, D>::count_pairs() { return state_->count_pairs(); }
template <class T, int D>
void WeaklyCompressibleSolver<T, D>::pressure_relaxation_pass() { state_->pressure_relaxation_pass(); }

}  // namespace unisph::sph
