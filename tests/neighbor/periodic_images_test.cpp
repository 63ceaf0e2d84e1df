// Periodic boundaries as ghost images (neighbor/periodic_images.hpp), on every policy, 2D and
// 3D, float and double, with one, two or all axes periodic:
//   * the neighbours found through the cell list over owned particles + images (inner relation,
//     direct search and stored lists, cells of the cutoff and of cutoff / 2; and a contact
//     relation) are the brute-force minimum-image neighbours: the same source particles, each
//     once, with r_ij the minimum-image displacement to round-off;
//   * on a lattice whose arithmetic is exact, every particle has 8 (2D) or 26 (3D) neighbours
//     with all axes periodic, r_ij exactly the minimum image;
//   * every image exists exactly once, corners and edges included (2^k - 1 for a particle near
//     k periodic faces), in the order (source, image code), the same bits on every policy;
//   * wrap() brings particles back into the box and leaves the others alone;
//   * refresh() copies typed and named variables (any element size) and shifts positions;
//   * a box narrower than two cutoffs along a periodic axis is one clear unisph::Error line.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "neighbor/minimum_image_reference.hpp"
#include "support/policy_test.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/periodic_images.hpp"
#include "unisph/particles/body.hpp"

namespace {
using namespace unisph;
using namespace unisph::testing;

// A box that is not the unit cube and does not start at the origin, with one side of exactly
// two cutoffs (the narrowest allowed; the bands of the two faces then overlap by the padding of
// the ghost width) when `narrow`. Binary fractions: the faces and lengths are exact in float.
template <class T, int D>
Box<T, D> test_box(bool narrow) {
  Box<T, D> box;
  const double lower[3] = {-0.375, 0.25, 1.0}, width[3] = {1.0, 0.75, 0.5};
  for (int a = 0; a < D; ++a) {
    box.lower[a] = T(lower[a]);
    box.upper[a] = T(lower[a] + ((narrow && a == D - 1) ? 0.25 : width[a]));
  }
  return box;
}

template <class T, int D, class P>
void check_minimum_image(P policy) {
  const T cutoff = T(0.125);
  for (bool narrow : {false, true})
    for (std::array<bool, D> periodic : axis_choices<T, D>())
      for (int split : {1, 2})
        for (SearchMethod method : {SearchMethod::direct, SearchMethod::stored}) {
          SCOPED_TRACE((describe<T, D>(periodic)) + (narrow ? ", a side of two cutoffs" : "") + ", cells of cutoff / " +
                       std::to_string(split) + (method == SearchMethod::direct ? ", direct" : ", stored"));
          const Box<T, D> box = test_box<T, D>(narrow);
          const Index n = D == 2 ? 600 : 1500;
          const std::vector<Vec<T, D>> x = random_positions(box, n, 11 + split + 3 * D);
          Body<T, D> body("Fluid", box, n);
          body.positions().assign(x);
          PeriodicImages<T, D> images(body.particles(), body.positions(), box, periodic, cutoff);
          images.wrap(policy);
          images.build(policy);
          ASSERT_GT(images.ghost_count(), 0u);
          T cell = cutoff / T(split);
          while (T(split) * cell < cutoff) cell = std::nextafter(cell, cutoff);
          CellLinkedList<T, D> cells(body.positions(), images.search_box(), cutoff, OutsideParticles::flag, cell);
          cells.build(policy);
          const CellListReport report = cells.report();
          EXPECT_EQ(report.out_of_box, 0u) << "images outside the search box";
          InnerRelation<T, D> inner(cells, method);
          inner.set_source_count(n);
          inner.update(policy);

          const double tol = coordinate_tolerance(box);
          const auto ref = minimum_image<T, D>(x, x, box, periodic, cutoff, true, tol);
          Index capacity = 1;
          for (const auto& r : ref) capacity = std::max<Index>(capacity, r.size() + 1);
          const std::vector<std::uint32_t> image_source = images.sources().to_vector();
          Index pairs = 0;
          const Index bad = compare<T, D>(collect(policy, inner.search(policy), n, capacity, image_source, n), ref, tol,
                                          pairs);
          EXPECT_EQ(bad, 0u);
          EXPECT_GT(pairs, Index(n) * (D == 2 ? 5 : 10));

          // Another body's particles (inside the box, as a periodic domain keeps them) as sources.
          if (method == SearchMethod::direct && split == 1) {
            const std::vector<Vec<T, D>> y = random_positions(box, 200, 5);
            DiscreteVariable<Vec<T, D>> other("Other");
            other.assign(y);
            ContactRelation<T, D> contact(other, cells);
            contact.update(policy);
            const auto cref = minimum_image<T, D>(y, x, box, periodic, cutoff, false, tol);
            Index cap = 1;
            for (const auto& r : cref) cap = std::max<Index>(cap, r.size() + 1);
            const Index contact_bad =
                compare<T, D>(collect(policy, contact.search(policy), y.size(), cap, image_source, n), cref, tol, pairs);
            EXPECT_EQ(contact_bad, 0u) << "contact relation";
          }
        }
}

// The lattice 0, 1/16, ..., 15/16 along each axis in [0, 1), all axes periodic, cutoff 1/8:
// every sum is exact, pairs at exactly the cutoff are out, so every particle has the 8 (2D) or
// 26 (3D) lattice neighbours, r_ij exactly the minimum image.
template <class T, int D, class P>
void check_lattice(P policy) {
  const int side = 16;
  Index n = 1;
  for (int a = 0; a < D; ++a) n *= side;
  std::vector<Vec<T, D>> x(n);
  for (Index k = 0; k < n; ++k) {
    Index r = k;
    for (int a = 0; a < D; ++a, r /= side) x[k][a] = T(r % side) / T(side);
  }
  const Box<T, D> box{Vec<T, D>::constant(T(0)), Vec<T, D>::constant(T(1))};
  std::array<bool, D> periodic;
  periodic.fill(true);
  Body<T, D> body("Lattice", box, n);
  body.positions().assign(x);
  PeriodicImages<T, D> images(body.particles(), body.positions(), box, periodic, T(0.125));
  images.build(policy);
  CellLinkedList<T, D> cells(body.positions(), images.search_box(), T(0.125));
  cells.build(policy);
  InnerRelation<T, D> inner(cells, SearchMethod::direct);
  inner.set_source_count(n);
  const auto found = collect(policy, inner.search(policy), n, 40, images.sources().to_vector(), n);
  const auto ref = minimum_image<T, D>(x, x, box, periodic, T(0.125), true, 0.0);
  Index pairs = 0;
  const Index bad = compare<T, D>(found, ref, 0.0, pairs);
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(pairs, n * (D == 2 ? 8 : 26));
  for (const auto& f : found) EXPECT_EQ(f.size(), D == 2 ? 8u : 26u);
}

// Images by construction (independently of the header): (source, code) for every owned
// particle and every combination of the shifts its faces allow, in ascending (source, code).
template <class T, int D>
std::vector<std::pair<std::uint32_t, std::uint32_t>> expected_images(const std::vector<Vec<T, D>>& x,
                                                                     const Box<T, D>& box,
                                                                     std::array<bool, D> periodic, T width) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<std::vector<unsigned>> digits(D);
    for (int a = 0; a < D; ++a) {
      digits[a].push_back(0);
      if (periodic[a] && x[i][a] - box.lower[a] < width) digits[a].push_back(1);
      if (periodic[a] && box.upper[a] - x[i][a] < width) digits[a].push_back(2);
    }
    std::vector<unsigned> codes{0};
    unsigned weight = 1;
    for (int a = 0; a < D; ++a, weight *= 3) {
      std::vector<unsigned> next;
      for (unsigned c : codes)
        for (unsigned d : digits[a]) next.push_back(c + d * weight);
      codes = next;
    }
    std::sort(codes.begin(), codes.end());
    for (unsigned c : codes)
      if (c != 0) out.emplace_back(std::uint32_t(i), c);
  }
  return out;
}

template <class T, int D, class P>
void check_bookkeeping(P policy) {
  const T cutoff = T(0.125);
  for (std::array<bool, D> periodic : axis_choices<T, D>()) {
    const std::string what = describe<T, D>(periodic);
    SCOPED_TRACE(what);
    const Box<T, D> box = test_box<T, D>(false);
    const Index n = D == 2 ? 700 : 2000;
    std::vector<Vec<T, D>> x = random_positions(box, n, 3);
    // Particles in every corner, at a quarter cutoff from each face: 2^k - 1 images each.
    for (unsigned corner = 0; corner < (1u << D); ++corner)
      for (int a = 0; a < D; ++a)
        x[100 + corner][a] = (corner >> a) & 1u ? box.upper[a] - cutoff / 4 : box.lower[a] + cutoff / 4;
    Body<T, D> body("Fluid", box, n);
    body.positions().assign(x);
    PeriodicImages<T, D> images(body.particles(), body.positions(), box, periodic, cutoff);
    images.build(policy);
    EXPECT_EQ(body.particles().ghost_count(), images.ghost_count());
    EXPECT_EQ(body.positions().size(), n + images.ghost_count());

    const auto expected = expected_images<T, D>(x, box, periodic, images.ghost_width());
    const std::vector<std::uint32_t> sources = images.sources().to_vector(), codes = images.codes().to_vector();
    ASSERT_EQ(sources.size(), expected.size());
    std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
    const std::vector<Vec<T, D>> all = body.positions().to_vector();
    for (std::size_t g = 0; g < sources.size(); ++g) {
      EXPECT_EQ(std::make_pair(sources[g], codes[g]), expected[g]) << "image " << g;
      EXPECT_TRUE(seen.emplace(sources[g], codes[g]).second) << "image " << g << " twice";
      EXPECT_EQ(all[n + g], x[sources[g]] + images.shift(codes[g])) << "image " << g;
    }
    // Corners: every combination of the periodic axes.
    int k = 0;
    for (int a = 0; a < D; ++a) k += periodic[a];
    for (unsigned corner = 0; corner < (1u << D); ++corner)
      EXPECT_EQ(std::count(sources.begin(), sources.end(), 100 + corner), (1 << k) - 1) << "corner " << corner;

    // The same images, bit for bit, as seq builds them.
    Body<T, D> again("Fluid", box, n);
    again.positions().assign(x);
    PeriodicImages<T, D> seq_images(again.particles(), again.positions(), box, periodic, cutoff);
    seq_images.build(seq);
    EXPECT_TRUE(seq_images.sources().to_vector() == sources);
    EXPECT_TRUE(seq_images.codes().to_vector() == codes);
    EXPECT_TRUE(again.positions().to_vector() == all);

    // A second build after the particles moved: the ghost count follows.
    for (auto& p : x) p[0] = box.lower[0] + (p[0] - box.lower[0]) * T(0.5);
    body.particles().set_ghost_count(0);
    body.positions().assign(x);
    images.build(policy);
    const auto expected2 = expected_images<T, D>(x, box, periodic, images.ghost_width());
    EXPECT_EQ(images.ghost_count(), expected2.size());
    EXPECT_EQ(images.builds(), 2u);
  }
}

template <class T, int D, class P>
void check_wrap(P policy) {
  const Box<T, D> box = test_box<T, D>(false);
  std::array<bool, D> periodic{};
  periodic[0] = true;
  periodic[D - 1] = true;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  std::vector<Vec<T, D>> x = random_positions(box, 400, 9);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> far(-3.0, 3.0);
  for (std::size_t k = 20; k < 300; ++k)  // beyond the faces by up to three box widths
    for (int a = 0; a < D; ++a) x[k][a] = T(box.lower[a] + far(rng) * (box.upper[a] - box.lower[a]));
  x[300][0] = box.upper[0];
  x[301][0] = box.lower[0];
  x[302][0] = std::nextafter(box.lower[0], -inf);
  x[303][0] = std::nextafter(box.upper[0], inf);
  x[304][0] = nan;
  x[305][0] = inf;
  Body<T, D> body("Fluid", box, x.size());
  body.positions().assign(x);
  PeriodicImages<T, D> images(body.particles(), body.positions(), box, periodic, T(0.125));
  images.wrap(policy);
  const std::vector<Vec<T, D>> y = body.positions().to_vector();
  for (std::size_t k = 0; k < x.size(); ++k)
    for (int a = 0; a < D; ++a) {
      const T before = x[k][a], after = y[k][a];
      const bool inside = box.lower[a] <= before && before <= box.upper[a];
      if (!periodic[a] || inside || !std::isfinite(before)) {
        EXPECT_TRUE(std::memcmp(&before, &after, sizeof(T)) == 0) << "particle " << k << " axis " << a << " moved";
        continue;
      }
      EXPECT_GE(after, box.lower[a]) << "particle " << k << " axis " << a;
      EXPECT_LE(after, box.upper[a]) << "particle " << k << " axis " << a;
      const double L = double(box.upper[a]) - double(box.lower[a]);
      const double turns = (double(before) - double(after)) / L;
      EXPECT_NEAR(turns, std::round(turns), 1e-5) << "particle " << k << " axis " << a;
    }
  // The same bits as seq.
  Body<T, D> again("Fluid", box, x.size());
  again.positions().assign(x);
  PeriodicImages<T, D>(again.particles(), again.positions(), box, periodic, T(0.125)).wrap(seq);
  const std::vector<Vec<T, D>> z = again.positions().to_vector();
  EXPECT_TRUE(std::memcmp(z.data(), y.data(), y.size() * sizeof(Vec<T, D>)) == 0);
}

struct Odd3 {  // a 3-byte element, copied byte by byte
  unsigned char b[3];
};

template <class T, int D, class P>
void check_refresh(P policy) {
  const Box<T, D> box = test_box<T, D>(false);
  std::array<bool, D> periodic;
  periodic.fill(true);
  const Index n = 500;
  std::vector<Vec<T, D>> x = random_positions(box, n, 21);
  Body<T, D> body("Fluid", box, n);
  body.positions().assign(x);
  DiscreteVariable<Vec<T, D>>& velocity = body.particles().template add_variable<Vec<T, D>>("Velocity");
  DiscreteVariable<T>& density = body.particles().template add_variable<T>("Density");
  DiscreteVariable<Odd3>& odd = body.particles().template add_variable<Odd3>("Odd");
  PeriodicImages<T, D> images(body.particles(), body.positions(), box, periodic, T(0.125));
  images.build(policy);
  const Index g = images.ghost_count();
  ASSERT_GT(g, 0u);
  ASSERT_EQ(velocity.size(), n + g);
  // New owned values (ghost slots hold junk), positions moved a little.
  std::vector<Vec<T, D>> v(n + g), xs = body.positions().to_vector();
  std::vector<T> rho(n + g, T(-1));
  std::vector<Odd3> o(n + g, Odd3{{9, 9, 9}});
  for (Index i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) v[i][a] = T(i) + T(a) / T(4);
    rho[i] = T(1000) + T(i);
    o[i] = Odd3{{static_cast<unsigned char>(i), static_cast<unsigned char>(i >> 8), 7}};
    xs[i][0] += T(0.001);
  }
  velocity.assign(v);
  density.assign(rho);
  odd.assign(o);
  body.positions().assign(xs);
  images.refresh(policy, velocity, density, body.positions());
  images.refresh(policy, {"Odd"});
  const std::vector<std::uint32_t> src = images.sources().to_vector(), codes = images.codes().to_vector();
  const auto v2 = velocity.to_vector();
  const auto rho2 = density.to_vector();
  const auto o2 = odd.to_vector();
  const auto x2 = body.positions().to_vector();
  for (Index k = 0; k < g; ++k) {
    EXPECT_EQ(v2[n + k], v[src[k]]);
    EXPECT_EQ(rho2[n + k], rho[src[k]]);
    EXPECT_EQ(std::memcmp(o2[n + k].b, o[src[k]].b, 3), 0);
    EXPECT_EQ(x2[n + k], xs[src[k]] + images.shift(codes[k]));
  }
  for (Index i = 0; i < n; ++i) EXPECT_EQ(x2[i], xs[i]);
  // A variable that is not the set's is refused.
  DiscreteVariable<T> stranger("Stranger", n);
  EXPECT_THROW(images.refresh(policy, stranger), Error);
}

UNISPH_POLICY_TEST_SUITE(PeriodicImagesTest);

TYPED_TEST(PeriodicImagesTest, MinimumImageNeighbors2D) {
  check_minimum_image<float, 2>(this->policy);
  check_minimum_image<double, 2>(this->policy);
}
TYPED_TEST(PeriodicImagesTest, MinimumImageNeighbors3D) {
  check_minimum_image<float, 3>(this->policy);
  check_minimum_image<double, 3>(this->policy);
}
TYPED_TEST(PeriodicImagesTest, LatticeHasEveryNeighborAcrossFacesEdgesAndCorners) {
  check_lattice<float, 2>(this->policy);
  check_lattice<double, 3>(this->policy);
}
TYPED_TEST(PeriodicImagesTest, EveryImageOnceInTheSameOrderOnEveryPolicy) {
  check_bookkeeping<float, 2>(this->policy);
  check_bookkeeping<double, 2>(this->policy);
  check_bookkeeping<float, 3>(this->policy);
  check_bookkeeping<double, 3>(this->policy);
}
TYPED_TEST(PeriodicImagesTest, WrapBringsParticlesBackIntoTheBox) {
  check_wrap<float, 2>(this->policy);
  check_wrap<double, 3>(this->policy);
}
TYPED_TEST(PeriodicImagesTest, RefreshCopiesVariablesAndShiftsPositions) {
  check_refresh<float, 2>(this->policy);
  check_refresh<double, 3>(this->policy);
}

TEST(HostPeriodicImages, BoxNarrowerThanTwoCutoffsIsRefused) {
  const Box<double, 3> box{{{0, 0, 0}}, {{1, 0.2, 1}}};
  Body<double, 3> body("Water", box, 10);
  try {
    PeriodicImages<double, 3> images(body.particles(), body.positions(), box, {false, true, false}, 0.125);
    FAIL() << "a box 0.2 wide along a periodic axis with cutoff 0.125 was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find("PeriodicImages of 'Water'"), std::string::npos) << what;
    EXPECT_NE(what.find("periodic axis 1"), std::string::npos) << what;
    EXPECT_NE(what.find("ghost images would be wider than the domain"), std::string::npos) << what;
  }
  // The same width along an axis that is not periodic is fine, and exactly two cutoffs too.
  EXPECT_NO_THROW((PeriodicImages<double, 3>(body.particles(), body.positions(), box, {true, false, true}, 0.125)));
  EXPECT_NO_THROW((PeriodicImages<double, 3>(body.particles(), body.positions(), box, {true, true, true}, 0.1)));
}

TEST(HostPeriodicImages, SearchBoxExtendsPeriodicAxesOnly) {
  const Box<float, 2> box{{{-1, 0}}, {{1, 0.5f}}};
  Body<float, 2> body("Water", box, 0);
  PeriodicImages<float, 2> images(body.particles(), body.positions(), box, {true, false}, 0.1f);
  const Box<float, 2> s = images.search_box();
  EXPECT_LT(s.lower[0], -1.1f + 1e-6f);
  EXPECT_GT(s.upper[0], 1.1f - 1e-6f);
  EXPECT_EQ(s.lower[1], 0.0f);
  EXPECT_EQ(s.upper[1], 0.5f);
  EXPECT_GE(images.ghost_width(), 0.1f);
  EXPECT_LT(images.ghost_width(), 0.1001f);
  images.build(seq);  // no particles: no images
  EXPECT_EQ(images.ghost_count(), 0u);
}

}  // namespace
