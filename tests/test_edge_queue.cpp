// The split and collapse passes' queue (engine/remesh/edge_queue.h): under
// any mix of pushes and pops it takes the edges in the order of their ranks
// (LongestFirst, ShortestFirst), as a sorted reference does, and its storage
// serves pass after pass.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "remesh/edge_queue.h"

using namespace anisurf::remesh;

namespace {

// An edge in the reference order: the rank, then the second vertex; the
// corner tells apart copies of one edge (they may come out in either order).
using Ref = std::tuple<std::uint64_t, int, int>;

// Keys spread over many octaves (and so many buckets), with exact repeats
// (equal keys fall back on the slots) and a few zeros and infinities.
float random_key(std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, 99);
  const int p = pick(rng);
  if (p == 0) return 0.0f;
  if (p == 1) return INFINITY;
  if (p < 30) return static_cast<float>(0.25 * (1 + pick(rng) % 4));
  std::uniform_real_distribution<double> exponent(-12, 12);
  return static_cast<float>(std::exp2(exponent(rng)));
}

template <class Order>
void check_one_pass(EdgeQueueStorage& storage, std::mt19937& rng, int n_initial, int n_steps) {
  EdgeQueue<Order> q(storage);
  std::multiset<Ref> ref;
  std::uniform_int_distribution<int> slot(0, 200);
  int corner = 0;
  for (int i = 0; i < n_initial; ++i) {
    const float key = random_key(rng);
    const int a = slot(rng), b = slot(rng);
    q.append(key, a, b, corner);
    ref.insert({Order::rank(key, a), b, corner++});
  }
  q.start();
  CHECK(q.size() == ref.size());
  // Takes one edge: the one taken (its corner names it) has the least rank
  // and second vertex left (of edges equal in both, any may come first).
  auto take_least = [&] {
    REQUIRE_FALSE(q.empty());
    const QueuedEdgeTaken got = q.pop();
    const Ref& least = *ref.begin();
    const auto it = ref.find(Ref{std::get<0>(least), got.b, got.corner});
    REQUIRE(it != ref.end());
    REQUIRE(std::get<1>(*it) == std::get<1>(least));
    ref.erase(it);
  };
  std::uniform_int_distribution<int> coin(0, 2);
  for (int step = 0; step < n_steps; ++step) {
    if (coin(rng) == 0 || ref.empty()) {
      const float key = random_key(rng);
      const int a = slot(rng), b = slot(rng);
      q.push(key, a, b, corner);
      ref.insert({Order::rank(key, a), b, corner++});
    } else {
      take_least();
    }
    REQUIRE(q.size() == ref.size());
  }
  while (!ref.empty()) take_least();  // the rest, in order
  CHECK(q.empty());
}

}  // namespace

TEST_CASE("edge queue: pushes and pops in any mix take the edges by rank, longest or shortest first") {
  std::mt19937 rng(7);
  EdgeQueueStorage storage;
  // Passes of several sizes on one storage (kept from pass to pass), a pass
  // left unfinished between them (its storage is reset by the next).
  for (int pass = 0; pass < 6; ++pass) {
    check_one_pass<ShortestFirst>(storage, rng, pass * 700, 3000);
    check_one_pass<LongestFirst>(storage, rng, pass * 500 + 3, 2000);
  }
  {
    EdgeQueue<ShortestFirst> unfinished(storage);
    unfinished.append(1.0f, 1, 2, 0);
    unfinished.start();
    unfinished.push(0.5f, 3, 4, 1);
  }
  check_one_pass<ShortestFirst>(storage, rng, 100, 300);
}

TEST_CASE("edge queue: the orders - the key first, then the first slot, then the second") {
  EdgeQueueStorage storage;
  {
    EdgeQueue<ShortestFirst> q(storage);
    q.append(0.5f, 9, 1, 0);
    q.append(0.25f, 7, 3, 1);
    q.append(0.5f, 2, 8, 2);
    q.append(0.5f, 2, 5, 3);
    q.start();
    q.push(0.3f, 1, 1, 4);
    const int expected_corners[] = {1, 4, 3, 2, 0};  // 0.25; 0.3; 0.5 from slot 2 (to 5, then 8), then slot 9
    for (int c : expected_corners) CHECK(q.pop().corner == c);
    CHECK(q.empty());
  }
  {
    EdgeQueue<LongestFirst> q(storage);
    q.append(0.5f, 9, 1, 0);
    q.append(2.0f, 7, 3, 1);
    q.append(0.5f, 2, 8, 2);
    q.start();
    q.push(1.0f, 4, 1, 3);
    q.push(0.5f, 2, 6, 4);
    const int expected_corners[] = {1, 3, 4, 2, 0};  // 2; 1; 0.5 from slot 2 (to 6, then 8), then slot 9
    for (int c : expected_corners) CHECK(q.pop().corner == c);
    CHECK(q.empty());
  }
}
