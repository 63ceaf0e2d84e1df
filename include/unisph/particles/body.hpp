#pragma once
// Body<T, D>: a named group of particles (a fluid, a wall) that owns its particle set and
// registers its positions ("Position": sortable, output). The domain is the box its cell
// linked lists cover.

#include <string>

#include "unisph/core/box.hpp"
#include "unisph/particles/particle_set.hpp"

namespace unisph {

template <class T, int D>
inline constexpr VariableTag<Vec<T, D>> position_tag{"Position"};

template <class T, int D>
class Body {
 public:
  using Position = Vec<T, D>;

  Body(std::string name, const Box<T, D>& domain, Index owned_count, Index ghost_count = 0,
       std::uint64_t first_id = 0, SetShare share = {})
      : name_(std::move(name)),
        domain_(domain),
        particles_(name_, owned_count, ghost_count, first_id, share),
        positions_(particles_.add_variable(position_tag<T, D>, sortable_output_variable)) {}

  const std::string& name() const { return name_; }
  const Box<T, D>& domain() const { return domain_; }
  void set_domain(const Box<T, D>& domain) { domain_ = domain; }
  ParticleSet& particles() { return particles_; }
  DiscreteVariable<Position>& positions() { return positions_; }

 private:
  std::string name_;
  Box<T, D> domain_;
  ParticleSet particles_;
  DiscreteVariable<Position>& positions_;
};

}  // namespace unisph
