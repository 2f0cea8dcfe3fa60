// FlatMap64 (engine/core/flat_map64.h), the refusal memo's map: under random
// insertions, overwrites, erasures (backward shifts across the wrap of the
// array included), clears and swaps it holds what a std::unordered_map holds.
#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <unordered_map>

#include "core/flat_map64.h"

using anisurf::FlatMap64;

namespace {

// Every key of the reference found with its value, and the sizes equal.
bool same(FlatMap64<int>& m, const std::unordered_map<std::uint64_t, int>& ref) {
  if (m.size() != ref.size()) return false;
  for (const auto& [k, v] : ref) {
    const int* found = m.find(k);
    if (!found || *found != v) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("flat map: random insertions, erasures, clears and swaps agree with std::unordered_map") {
  std::mt19937_64 rng(11);
  FlatMap64<int> a, b;
  std::unordered_map<std::uint64_t, int> ra, rb;
  // Keys from a small range (many collisions, overwrites and erasures of
  // present keys) and from the whole range (edge keys of large slots).
  auto random_key = [&] {
    const std::uint64_t k = rng() % 3 == 0 ? rng() % 700 : (rng() % 5000) << 32 | (rng() % 5000);
    return k == FlatMap64<int>::kEmpty ? 0 : k;
  };
  for (int step = 0; step < 200000; ++step) {
    const int op = static_cast<int>(rng() % 100);
    const std::uint64_t k = random_key();
    if (op < 45) {
      const int v = static_cast<int>(rng() % 1000);
      CHECK(*a.insert_or_assign(k, v) == v);
      ra[k] = v;
    } else if (op < 80) {
      CHECK(a.erase(k) == (ra.erase(k) == 1));
    } else if (op < 98) {
      const int* found = a.find(k);
      const auto it = ra.find(k);
      REQUIRE((found != nullptr) == (it != ra.end()));
      if (found) CHECK(*found == it->second);
    } else if (op < 99) {
      a.swap(b);
      ra.swap(rb);
    } else if (step % 7 == 0) {
      a.clear();
      ra.clear();
    }
    if (step % 5000 == 0) {
      REQUIRE(same(a, ra));
      REQUIRE(same(b, rb));
    }
  }
  CHECK(same(a, ra));
  CHECK(same(b, rb));
  // Small maps (16 slots, at most 7 keys): runs often wrap around the end
  // of the array; every key checked after every erasure.
  for (int trial = 0; trial < 20000; ++trial) {
    FlatMap64<int> m;
    std::unordered_map<std::uint64_t, int> r;
    for (int i = 0; i < 7; ++i) {
      const std::uint64_t k = rng() % 40;
      m.insert_or_assign(k, i);
      r[k] = i;
    }
    for (int i = 0; i < 4; ++i) {
      const std::uint64_t k = rng() % 40;
      CHECK(m.erase(k) == (r.erase(k) == 1));
      REQUIRE(same(m, r));
    }
  }
  // Emptied, it finds nothing and takes keys again.
  a.clear();
  CHECK(a.empty());
  CHECK(a.find(5) == nullptr);
  CHECK_FALSE(a.erase(5));
  a.insert_or_assign(5, 1);
  CHECK(*a.find(5) == 1);
}
