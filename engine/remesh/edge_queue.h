// The queue of the edges a split or collapse pass (report section 6: the
// longest edges split first, the shortest collapsed first) takes one by one:
// a bucket queue whose storage a Remesher keeps from pass to pass.
//
//   EdgeQueueStorage storage;
//   EdgeQueue<ShortestFirst> q(storage);
//   for (...) q.append(key, a, b, corner);   // the edges of the pass's start
//   q.start();
//   while (!q.empty()) { QueuedEdgeTaken e = q.pop(); ... q.push(key, v, w, -1); }
//
// The order: the least rank first (ShortestFirst: the shortest key, then the
// lowest first slot, then the lowest second slot; LongestFirst: the longest
// key first, then the same). Every order of pushes and pops takes the edges
// in that order.
#pragma once
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace anisurf::remesh {

// Ranks: a key is a length (never negative, so its bits order as the floats
// do) in the high half, the first slot in the low half; the least is taken
// first.
struct LongestFirst {
  static std::uint64_t rank(float key, int a) {
    return std::uint64_t{~std::bit_cast<std::uint32_t>(key)} << 32 | static_cast<std::uint32_t>(a);
  }
};
struct ShortestFirst {
  static std::uint64_t rank(float key, int a) {
    return std::uint64_t{std::bit_cast<std::uint32_t>(key)} << 32 | static_cast<std::uint32_t>(a);
  }
};

struct QueuedEdge {
  std::uint64_t rank;  // the order (LongestFirst or ShortestFirst)
  int b;               // the second vertex (the first is the rank's low half)
  int corner;          // the corner naming a -> b when queued, or -1
};
struct QueuedEdgeTaken {
  int a, b, corner;
};

// The storage of an EdgeQueue: the edges of the pass's start in one array,
// grouped by bucket (a range per bucket, sorted when the pass first takes
// from it), and a heap per bucket for the edges pushed during the pass.
struct EdgeQueueStorage {
  std::vector<QueuedEdge> initial;
  std::vector<int> cursor, end;                 // per bucket: its range of `initial` still to take
  std::vector<std::uint8_t> sorted;             // per bucket: its range is sorted
  std::vector<std::vector<QueuedEdge>> pushed;  // per bucket: a heap, the least on top
  std::vector<std::uint64_t> live;              // a bit per bucket holding edges
};

// A bucket queue: the top 12 bits of a rank (the key's sign, exponent and 3
// leading mantissa bits: 8 buckets an octave) choose its bucket; the least
// rank of the least bucket holding edges comes first. Every take reads the
// next edge of a sorted range or the top of a heap holding only the edges of
// one bucket pushed since: a coarsening's queue of a million edges is walked
// in order instead of sifting each take through a heap that misses the cache
// at every level.
template <class Order>
class EdgeQueue {
 public:
  static constexpr int kBuckets = 4096;

  explicit EdgeQueue(EdgeQueueStorage& s) : s_(s) {
    s_.initial.clear();
    s_.cursor.assign(kBuckets, 0);
    s_.end.assign(kBuckets, 0);
    s_.sorted.assign(kBuckets, 0);
    s_.live.assign(kBuckets / 64, 0);
    if (s_.pushed.size() != kBuckets) s_.pushed.resize(kBuckets);
  }
  // Storage is kept for the next pass unless it grew large (the first
  // refinement or coarsening passes): memory goes back while the mesh is big.
  ~EdgeQueue() {
    if (s_.initial.capacity() > 65536) std::vector<QueuedEdge>().swap(s_.initial);
    for (std::vector<QueuedEdge>& h : s_.pushed) {
      if (h.capacity() > 4096) std::vector<QueuedEdge>().swap(h);
      h.clear();
    }
  }
  EdgeQueue(const EdgeQueue&) = delete;
  EdgeQueue& operator=(const EdgeQueue&) = delete;

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  // Room for n edges of the pass's start (an array grown by doubling would
  // hold its old and new storage together at each step).
  void reserve(std::size_t n) { s_.initial.reserve(n); }
  // Adds an edge of the pass's start: start() follows the last one, before
  // any push or pop.
  void append(float key, int a, int b, int corner) { s_.initial.push_back({Order::rank(key, a), b, corner}); }
  // Groups the edges appended by bucket in place (each moved at most once
  // into its bucket's range).
  void start() {
    std::vector<QueuedEdge>& v = s_.initial;
    for (const QueuedEdge& x : v) ++s_.end[bucket(x.rank)];
    int offset = 0;
    for (int i = 0; i < kBuckets; ++i) {
      const int n = s_.end[i];
      s_.cursor[i] = offset;
      offset += n;
      s_.end[i] = offset;
      if (n > 0) mark_live(i);
    }
    std::vector<int> fill(s_.cursor);
    for (int i = 0; i < kBuckets; ++i)
      while (fill[i] < s_.end[i]) {
        const int j = bucket(v[fill[i]].rank);
        if (j == i) {
          ++fill[i];
        } else {
          std::swap(v[fill[i]], v[fill[j]++]);
        }
      }
    size_ = v.size();
  }
  // Adds an edge during the pass.
  void push(float key, int a, int b, int corner) {
    const QueuedEdge x{Order::rank(key, a), b, corner};
    const int i = bucket(x.rank);
    std::vector<QueuedEdge>& h = s_.pushed[i];
    h.push_back(x);
    std::push_heap(h.begin(), h.end(), After());
    mark_live(i);
    ++size_;
  }
  // Takes the least edge (the queue must not be empty).
  QueuedEdgeTaken pop() {
    const int i = lowest_live();
    std::vector<QueuedEdge>& h = s_.pushed[i];
    QueuedEdge x;
    if (s_.cursor[i] < s_.end[i]) {
      if (!s_.sorted[i]) {
        std::sort(s_.initial.begin() + s_.cursor[i], s_.initial.begin() + s_.end[i], Before());
        s_.sorted[i] = 1;
      }
      const QueuedEdge& head = s_.initial[static_cast<std::size_t>(s_.cursor[i])];
      if (h.empty() || !After()(head, h.front())) {
        x = head;
        ++s_.cursor[i];
      } else {
        x = take_top(h);
      }
    } else {
      x = take_top(h);
    }
    if (s_.cursor[i] == s_.end[i] && h.empty()) s_.live[i / 64] &= ~(std::uint64_t{1} << (i % 64));
    --size_;
    return {static_cast<int>(static_cast<std::uint32_t>(x.rank)), x.b, x.corner};
  }

 private:
  static int bucket(std::uint64_t rank) { return static_cast<int>(rank >> 52); }
  // p is taken after q: a greater rank, or the same and a greater second vertex.
  struct After {
    bool operator()(const QueuedEdge& p, const QueuedEdge& q) const {
      return p.rank != q.rank ? p.rank > q.rank : p.b > q.b;
    }
  };
  struct Before {
    bool operator()(const QueuedEdge& p, const QueuedEdge& q) const { return After()(q, p); }
  };
  // std::push_heap with After keeps the least on top.
  static QueuedEdge take_top(std::vector<QueuedEdge>& h) {
    std::pop_heap(h.begin(), h.end(), After());
    const QueuedEdge x = h.back();
    h.pop_back();
    return x;
  }
  void mark_live(int i) {
    s_.live[i / 64] |= std::uint64_t{1} << (i % 64);
    lowest_ = std::min(lowest_, i);
  }
  // Every bucket holding edges is at lowest_ or above.
  int lowest_live() {
    int w = lowest_ / 64;
    std::uint64_t bits = s_.live[w] & (~std::uint64_t{0} << (lowest_ % 64));
    while (bits == 0) bits = s_.live[++w];
    lowest_ = 64 * w + std::countr_zero(bits);
    return lowest_;
  }

  EdgeQueueStorage& s_;
  std::size_t size_ = 0;
  int lowest_ = kBuckets;
};

}  // namespace anisurf::remesh
