#pragma once
// How many particles a relaxation pass runs over: every particle of its variables, or, in a
// periodic relaxation (ParticleRelaxation::make_periodic), the set's owned particles only, its
// images after them being read as neighbours and never moved, measured or counted.
#include "unisph/particles/particle_set.hpp"

namespace unisph {

class OwnedParticles {
 public:
  void count_owned_of(const ParticleSet& set) { set_ = &set; }
  // `all`: the size of the pass's variables.
  Index count(Index all) const { return set_ ? set_->owned_count() : all; }

 private:
  const ParticleSet* set_ = nullptr;
};

}  // namespace unisph
