// Atomics under the heaviest contention: every item hits one counter.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"

namespace {
using namespace unisph;

template <class T>
struct AddOne {
  View<T> counter;
  UNISPH_HOST_DEVICE void operator()(Index) const { atomic_add(&counter[0], T(1)); }
};

template <class T>
struct TakeTicket {
  View<T> counter;
  View<T> ticket;
  UNISPH_HOST_DEVICE void operator()(Index i) const { ticket[i] = atomic_fetch_add(&counter[0], T(1)); }
};

template <class T>
struct MinMaxOfItem {
  View<T> lo, hi;
  UNISPH_HOST_DEVICE static T value(Index i) { return static_cast<T>((i * 7919) % 100'003) - static_cast<T>(50'000); }
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    atomic_min(&lo[0], value(i));
    atomic_max(&hi[0], value(i));
  }
};

UNISPH_POLICY_TEST_SUITE(Atomic);

template <class T, class P>
void check_counter(P policy) {
  const Index n = 1'000'000;  // below 2^24: exact in float
  DiscreteVariable<T> counter("counter", 1);
  particle_for(policy, n, AddOne<T>{counter.read_write(policy)});
  EXPECT_EQ(counter.to_vector()[0], static_cast<T>(n));
}

TYPED_TEST(Atomic, AddUnderFullContention) {
  check_counter<int>(this->policy);
  check_counter<unsigned>(this->policy);
  check_counter<unsigned long long>(this->policy);
  check_counter<std::int64_t>(this->policy);
  check_counter<float>(this->policy);
  check_counter<double>(this->policy);
}

TYPED_TEST(Atomic, FetchAddHandsOutEveryTicketOnce) {
  const Index n = 1'000'003;
  DiscreteVariable<unsigned> counter("counter", 1), ticket("ticket", n);
  particle_for(this->policy, n, TakeTicket<unsigned>{counter.read_write(this->policy), ticket.write(this->policy)});
  std::vector<unsigned> t = ticket.to_vector();
  std::sort(t.begin(), t.end());
  Index wrong = 0;
  for (Index i = 0; i < n; ++i) wrong += t[i] != i;
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(counter.to_vector()[0], n);
}

// Item i increments counter key(i): runs of equal keys (as in a cell list of sorted
// particles), single items, alternating keys and keys that come back in a later run.
struct TakeSharedTicket {
  View<unsigned> counters;
  View<unsigned> ticket;
  View<const unsigned> key;
  UNISPH_HOST_DEVICE void operator()(Index i) const { ticket[i] = atomic_increment_shared(&counters[key[i]]); }
};

TYPED_TEST(Atomic, SharedIncrementHandsOutEveryTicketOncePerCounter) {
  const Index n = 200'003;
  std::vector<unsigned> keys(n);
  for (Index i = 0; i < n; ++i) {
    const Index block = i / 1000;
    switch (block % 5) {
      case 0: keys[i] = unsigned(i / 17) % 50; break;        // runs of 17, keys repeating later
      case 1: keys[i] = unsigned(i) % 50; break;             // every item its own run
      case 2: keys[i] = unsigned(i / 2) % 2; break;          // runs of 2 of two alternating keys
      case 3: keys[i] = 7; break;                            // one counter for 1000 items
      default: keys[i] = unsigned((i * 2654435761u) >> 7) % 50; break;  // scattered
    }
  }
  DiscreteVariable<unsigned> counters("counters", 50), ticket("ticket", n), key("key");
  key.assign(keys);
  particle_for(this->policy, n,
               TakeSharedTicket{counters.read_write(this->policy), ticket.write(this->policy), key.read(this->policy)});
  const std::vector<unsigned> t = ticket.to_vector(), c = counters.to_vector();
  std::vector<std::vector<unsigned>> per_key(50);
  for (Index i = 0; i < n; ++i) per_key[keys[i]].push_back(t[i]);
  Index wrong = 0;
  for (unsigned k = 0; k < 50; ++k) {
    std::sort(per_key[k].begin(), per_key[k].end());
    for (Index m = 0; m < per_key[k].size(); ++m) wrong += per_key[k][m] != m;
    wrong += c[k] != per_key[k].size();
  }
  EXPECT_EQ(wrong, 0u);
}

template <class T, class P>
void check_min_max(P policy) {
  const Index n = 1'000'003;
  DiscreteVariable<T> lo("lo", 1), hi("hi", 1);
  lo.assign(std::vector<T>{T(1e6)});
  hi.assign(std::vector<T>{T(-1e6)});
  particle_for(policy, n, MinMaxOfItem<T>{lo.read_write(policy), hi.read_write(policy)});
  T ref_lo = T(1e6), ref_hi = T(-1e6);
  for (Index i = 0; i < n; ++i) {
    ref_lo = std::min(ref_lo, MinMaxOfItem<T>::value(i));
    ref_hi = std::max(ref_hi, MinMaxOfItem<T>::value(i));
  }
  EXPECT_EQ(lo.to_vector()[0], ref_lo);
  EXPECT_EQ(hi.to_vector()[0], ref_hi);
}

TYPED_TEST(Atomic, MinMaxUnderFullContention) {
  check_min_max<int>(this->policy);
  check_min_max<long long>(this->policy);
  check_min_max<float>(this->policy);
  check_min_max<double>(this->policy);
}

}  // namespace
