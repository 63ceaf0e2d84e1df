#pragma once
// A body's values of a variable in the order of the particles' ids (independent of the sorts the
// solver made), owned particles only: for comparing two runs particle by particle.
#include <cstdint>
#include <string>
#include <vector>

#include "unisph/particles/body.hpp"

namespace unisph::testing {

template <class V, class T, int D>
std::vector<V> by_id(Body<T, D>& body, const std::string& variable) {
  ParticleSet& set = body.particles();
  const std::vector<std::uint64_t> ids = set.ids().to_vector();
  const std::vector<V> values = set.template variable<V>(variable).to_vector();
  std::vector<V> out(set.owned_count());
  for (Index i = 0; i < set.owned_count(); ++i) out[ids[i] - set.first_id()] = values[i];
  return out;
}

// The same for a vector variable (positions, velocities, normals).
template <class T, int D>
std::vector<Vec<T, D>> by_id(Body<T, D>& body, const std::string& variable) {
  return by_id<Vec<T, D>, T, D>(body, variable);
}

}  // namespace unisph::testing
