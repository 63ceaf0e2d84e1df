// Misuses of the views that must not compile, each with the sentence the user reads.
// tests/iter/CMakeLists.txt compiles this file once per UNISPH_CASE and expects the failure
// and the phrase (expect_compile_error.cmake).
#include <string>
#include <vector>

#include "unisph/iter/collective_for.hpp"
#include "unisph/iter/frame.hpp"
#include "unisph/iter/supercell.hpp"
#include "unisph/iter/view.hpp"

using namespace unisph;
struct Particle {
  int data[2];
};
using Frame = iter::Frame<Particle, 4>;

#if UNISPH_CASE == 1  // a container without traits
iter::View<std::vector<int>> view;
#elif UNISPH_CASE == 2  // a child view over the wrong container (non-const frames under const ones)
iter::View<iter::Supercell<const Frame>, iter::direction::Forward, iter::collectivity::None, iter::RuntimeTuple,
           iter::View<Frame>>
    view;
#elif UNISPH_CASE == 3  // a child under a level without children
iter::View<Frame, iter::direction::Forward, iter::collectivity::None, iter::RuntimeTuple, iter::View<Frame>> view;
#elif UNISPH_CASE == 4  // a jump of zero
iter::CompileTimeTuple<0, iter::all, 0> runtime;
#elif UNISPH_CASE == 5  // a particle type that cannot be copied byte for byte
iter::Frame<std::string, 4> frame;
#elif UNISPH_CASE == 6  // a direction that is not one
iter::View<Frame, int> view;
#elif UNISPH_CASE == 7  // a collective kernel without the team parameter
struct NotCollective {
  void operator()(Index) const {}
};
void launch() { iter::collective_for(seq, 1, 2, NotCollective{}); }
#else
#error "UNISPH_CASE names the misuse to compile (1..7)"
#endif
