// The communicator: rank and size, reductions and what they guarantee, the collective check.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "comm_test_support.hpp"
#include "unisph/comm/communicator.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;
using comm::Communicator;

struct ValueAt {
  const double* v;
  UNISPH_HOST_DEVICE double operator()(Index i) const { return v[i]; }
};

TEST(HostCommunicator, RankAndSize) {
  const Communicator c = Communicator::world();
  EXPECT_GE(c.rank(), 0);
  EXPECT_LT(c.rank(), c.size());
  if (c.size() > 1) {
    EXPECT_TRUE(comm::mpi_built());
  }
  const std::vector<std::uint64_t> ranks = c.allgather(std::uint64_t(c.rank()));
  ASSERT_EQ(ranks.size(), std::size_t(c.size()));
  for (int r = 0; r < c.size(); ++r) EXPECT_EQ(ranks[std::size_t(r)], std::uint64_t(r));
  EXPECT_GE(c.local_rank(), 0);
  EXPECT_LE(c.local_size(), c.size());
  const Communicator s = Communicator::serial();
  EXPECT_EQ(s.rank(), 0);
  EXPECT_EQ(s.size(), 1);
  EXPECT_EQ(s.allreduce_sum(2.5), 2.5);
}

TEST(HostCommunicator, MinMaxAndIntegerSumsAreExact) {
  const Communicator c = Communicator::world();
  const int r = c.rank(), p = c.size();
  EXPECT_EQ(c.allreduce_min(double(r) - 0.5), -0.5);
  EXPECT_EQ(c.allreduce_max(double(r) + 0.25), double(p - 1) + 0.25);
  EXPECT_EQ(c.allreduce_min(std::uint64_t(10 + r)), 10u);
  EXPECT_EQ(c.allreduce_max(std::uint64_t(10 + r)), std::uint64_t(10 + p - 1));
  const std::uint64_t big = std::uint64_t(1) << 60;
  EXPECT_EQ(c.allreduce_sum(big + std::uint64_t(r)), big * std::uint64_t(p) + std::uint64_t(p) * (p - 1) / 2);
  std::vector<std::uint64_t> v{std::uint64_t(r), 1, std::uint64_t(r) * r};
  c.allreduce_sum(v);
  std::uint64_t squares = 0;
  for (int q = 0; q < p; ++q) squares += std::uint64_t(q) * q;
  EXPECT_EQ(v, (std::vector<std::uint64_t>{std::uint64_t(p) * (p - 1) / 2, std::uint64_t(p), squares}));
}

TEST(HostCommunicator, DoubleSumFoldsInRankOrderOnEveryRank) {
  const Communicator c = Communicator::world();
  // Values of very different magnitudes: the association shows in the bits.
  const double x = c.rank() % 2 ? 1e-17 * (c.rank() + 1) : 1.0 + 1e-16 * c.rank();
  const double sum = c.allreduce_sum(x);
  const std::vector<double> all = c.allgather(x);
  double expected = all[0];
  for (std::size_t q = 1; q < all.size(); ++q) expected += all[q];
  EXPECT_EQ(std::bit_cast<std::uint64_t>(sum), std::bit_cast<std::uint64_t>(expected));
  // The same bits on every rank.
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(sum);
  EXPECT_EQ(c.allreduce_min(bits), c.allreduce_max(bits));
}

TEST(HostCommunicator, OrderedSumHasTheBitsOfOneRankForAnySplit) {
  const Communicator c = Communicator::world();
  for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(255), std::size_t(257), std::size_t(70001)}) {
    std::mt19937_64 rng(42 + n);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> global(n);
    for (std::size_t i = 0; i < n; ++i) global[i] = u(rng) * std::pow(10.0, double(i % 31) - 15);
    const std::size_t b = comm_test::slice_begin(n, c.rank(), c.size());
    const std::size_t e = comm_test::slice_begin(n, c.rank() + 1, c.size());
    const double sum = c.ordered_sum(std::span<const double>(global.data() + b, e - b));
    const double one_rank = deterministic_reduce(seq, n, Sum<double>{}, ValueAt{global.data()});
    EXPECT_EQ(std::bit_cast<std::uint64_t>(sum), std::bit_cast<std::uint64_t>(one_rank)) << "n = " << n;
  }
}

TEST(HostCommunicator, CombineOwnedGivesEachOwnersBits) {
  const Communicator c = Communicator::world();
  // Element k belongs to rank k % size; its value has every bit of its mantissa in use, a NaN
  // and an infinity among them.
  std::vector<double> expected(37);
  for (std::size_t k = 0; k < expected.size(); ++k) expected[k] = std::nextafter(1.0 / 3.0, 1.0) * std::pow(-7.0, double(k % 9) - 4);
  expected[5] = std::numeric_limits<double>::quiet_NaN();
  expected[6] = -std::numeric_limits<double>::infinity();
  std::vector<double> values(expected.size(), 0.0);
  for (std::size_t k = 0; k < values.size(); ++k)
    if (int(k % std::size_t(c.size())) == c.rank()) values[k] = expected[k];
  c.combine_owned(values);
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k == 5) EXPECT_TRUE(std::isnan(values[k]));
    else EXPECT_EQ(std::bit_cast<std::uint64_t>(values[k]), std::bit_cast<std::uint64_t>(expected[k])) << "element " << k;
  }
}

TEST(HostCommunicator, CheckAllPassesWhenEveryRankIsFine) {
  const Communicator c = Communicator::world();
  EXPECT_NO_THROW(c.check_all(true, "unused"));
}

TEST(HostCommunicator, CheckAllThrowsTheSameLineOnEveryRank) {
  const Communicator c = Communicator::world();
  const int failing = c.size() - 1;
  try {
    c.check_all(c.rank() != failing, "the particle file ends early");
    ADD_FAILURE() << "check_all returned although rank " << failing << " failed";
  } catch (const comm::RankFailure& f) {
    EXPECT_EQ(f.failed_rank(), failing);
    EXPECT_STREQ(f.what(), ("rank " + std::to_string(failing) + ": the particle file ends early").c_str());
  }
  // Two failing ranks: the first is named, the other counted.
  if (c.size() >= 2) {
    try {
      c.check_all(c.rank() == 0, "rank-specific reason " + std::to_string(c.rank()));
      ADD_FAILURE() << "check_all returned";
    } catch (const comm::RankFailure& f) {
      EXPECT_EQ(f.failed_rank(), 1);
      const std::string more = c.size() > 2 ? " (and " + std::to_string(c.size() - 2) + " more rank" +
                                                  (c.size() > 3 ? "s" : "") + ")"
                                            : "";
      EXPECT_EQ(std::string(f.what()), "rank 1: rank-specific reason 1" + more);
    }
  }
}

}  // namespace
