#pragma once
// The brute-force minimum-image reference of the periodic neighbour-search tests (ghost images,
// periodic_images_test.cpp; wrapped cell indices, periodic_cell_walk_test.cpp) and the
// comparison of what a search finds against it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "unisph/core/box.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/neighbor/neighbor_pair.hpp"

namespace unisph::testing {

// Each source's neighbours (j and r_ij) in fixed-capacity rows, through any search with
// for_each_neighbor(i, f) (NeighborSearch, PeriodicCellWalk).
template <class T, int D, class Search>
struct CollectPairs {
  Search search;
  Index capacity;
  View<std::uint32_t> found;
  View<Vec<T, D>> displacement;
  View<std::uint32_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Index c = 0;
    search.for_each_neighbor(i, [&](Index j, const NeighborPair<T, D>& pair) {
      if (c < capacity) {
        found[i * capacity + c] = static_cast<std::uint32_t>(j);
        displacement[i * capacity + c] = pair.r_ij;
      }
      ++c;
    });
    counts[i] = static_cast<std::uint32_t>(c);
  }
};

template <class T, int D>
struct Found {
  std::uint32_t source;  // the owned particle j is (or is an image of)
  Vec<T, D> r;
};

// The rows of CollectPairs as Found lists; j >= owned is an image, counted as image_source[j - owned].
template <template <class, int> class Search, class T, int D, class P>
std::vector<std::vector<Found<T, D>>> collect(P policy, const Search<T, D>& search, Index sources,
                                              Index capacity, const std::vector<std::uint32_t>& image_source,
                                              Index owned) {
  DiscreteVariable<std::uint32_t> found("found", sources * capacity), counts("counts", sources);
  DiscreteVariable<Vec<T, D>> r("r", sources * capacity);
  particle_for(policy, sources,
               CollectPairs<T, D, Search<T, D>>{search, capacity, found.write(policy), r.write(policy), counts.write(policy)});
  const std::vector<std::uint32_t> f = found.to_vector(), c = counts.to_vector();
  const std::vector<Vec<T, D>> d = r.to_vector();
  std::vector<std::vector<Found<T, D>>> out(sources);
  for (Index i = 0; i < sources; ++i) {
    EXPECT_LE(c[i], capacity) << "source " << i << " has more neighbours than any reference row";
    for (Index k = 0; k < std::min<Index>(c[i], capacity); ++k) {
      const std::uint32_t j = f[i * capacity + k];
      out[i].push_back({j < owned ? j : image_source.at(j - owned), d[i * capacity + k]});
    }
  }
  return out;
}

// The brute-force reference: x_i - x_j with L round(r / L) taken off along periodic axes, in
// double; `ambiguous` pairs are within round-off of the cutoff (either answer is right).
struct Reference {
  std::uint32_t j;
  std::array<double, 3> r;
  bool ambiguous;
};

template <class T, int D>
std::vector<std::vector<Reference>> minimum_image(const std::vector<Vec<T, D>>& sources,
                                                  const std::vector<Vec<T, D>>& targets, const Box<T, D>& box,
                                                  std::array<bool, D> periodic, T cutoff, bool inner, double tol) {
  std::vector<std::vector<Reference>> ref(sources.size());
  const double c2 = double(cutoff) * double(cutoff);
  for (std::size_t i = 0; i < sources.size(); ++i)
    for (std::size_t j = 0; j < targets.size(); ++j) {
      if (inner && i == j) continue;
      std::array<double, 3> r{};
      double r2 = 0;
      for (int a = 0; a < D; ++a) {
        r[a] = double(sources[i][a]) - double(targets[j][a]);
        if (periodic[a]) {
          const double L = double(box.upper[a]) - double(box.lower[a]);
          r[a] -= L * std::round(r[a] / L);
        }
        r2 += r[a] * r[a];
      }
      const bool ambiguous = std::abs(r2 - c2) <= 2 * double(cutoff) * tol;
      if (r2 < c2 || ambiguous) ref[i].push_back({std::uint32_t(j), r, ambiguous});
    }
  return ref;
}

// Found equals the reference: every clear pair once, nothing else but ambiguous pairs, each
// displacement within `tol` of the minimum image. Returns the number of mismatches.
template <class T, int D>
Index compare(const std::vector<std::vector<Found<T, D>>>& found, const std::vector<std::vector<Reference>>& ref,
              double tol, Index& pairs) {
  Index bad = 0;
  pairs = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    std::vector<Found<T, D>> f = found[i];
    std::sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.source < b.source; });
    for (std::size_t k = 1; k < f.size(); ++k)
      if (f[k].source == f[k - 1].source) {
        if (bad++ < 5) ADD_FAILURE() << "source " << i << " finds particle " << f[k].source << " twice";
      }
    std::size_t k = 0;
    for (const Reference& r : ref[i]) {
      while (k < f.size() && f[k].source < r.j) {
        if (bad++ < 5) ADD_FAILURE() << "source " << i << " finds " << f[k].source << ", not a neighbour";
        ++k;
      }
      if (k < f.size() && f[k].source == r.j) {
        for (int a = 0; a < D; ++a)
          if (!(std::abs(double(f[k].r[a]) - r.r[a]) <= tol)) {
            if (bad++ < 5)
              ADD_FAILURE() << "source " << i << ", neighbour " << r.j << ": r_ij[" << a << "] = " << f[k].r[a]
                            << ", minimum image " << r.r[a];
          }
        ++pairs;
        ++k;
      } else if (!r.ambiguous) {
        if (bad++ < 5) ADD_FAILURE() << "source " << i << " misses neighbour " << r.j;
      }
    }
    for (; k < f.size(); ++k)
      if (bad++ < 5) ADD_FAILURE() << "source " << i << " finds " << f[k].source << ", not a neighbour";
  }
  return bad;
}

template <class T, int D>
std::string describe(std::array<bool, D> periodic) {
  std::string s = std::to_string(D) + "D " + (sizeof(T) == 4 ? "float" : "double") + ", periodic axes {";
  for (int a = 0; a < D; ++a)
    if (periodic[a]) s += std::to_string(a) + (a + 1 < D ? " " : "");
  return s + "}";
}

// n positions uniform in the box (none on the upper faces), the first 8 moved onto the lower faces,
// edges and corners.
template <class T, int D>
std::vector<Vec<T, D>> random_positions(const Box<T, D>& box, Index n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec<T, D>> x(n);
  for (auto& p : x)
    for (int a = 0; a < D; ++a) {
      std::uniform_real_distribution<double> u(box.lower[a], box.upper[a]);
      p[a] = T(u(rng));
      if (p[a] >= box.upper[a]) p[a] = box.lower[a];
    }
  // A few on the faces, edges and corners exactly.
  for (Index k = 0; k < std::min<Index>(n, 8); ++k)
    for (int a = 0; a < D; ++a)
      if ((k >> a) & 1u) x[k][a] = box.lower[a];
  return x;
}

template <class T, int D>
double coordinate_tolerance(const Box<T, D>& box) {
  double largest = 0;
  for (int a = 0; a < D; ++a)
    largest = std::max({largest, std::abs(double(box.lower[a])), std::abs(double(box.upper[a]))});
  return 8 * double(std::numeric_limits<T>::epsilon()) * (largest + 1);
}

template <class T, int D>
std::vector<std::array<bool, D>> axis_choices() {
  if constexpr (D == 2)
    return {{true, false}, {false, true}, {true, true}};
  else
    return {{true, false, false}, {false, true, true}, {true, true, true}};
}

}  // namespace unisph::testing
