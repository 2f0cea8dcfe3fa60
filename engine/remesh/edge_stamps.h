// A map from edges (two vertex slots) to a 32-bit stamp, stored flat: open
// addressing with linear probing over an array of keys and one of stamps,
// 12 bytes a slot at a load between 0.5 and 0.8 (std::unordered_map spends
// about 32 bytes a node plus 8 a bucket, and a pointer chase per lookup).
// Used by the remesher's sag memo, which holds about one entry per edge.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace anisurf::remesh {

class EdgeStamps {
 public:
  // The key of edge {a, b} (vertex slots >= 0), the same for both orders.
  static std::uint64_t key(int a, int b) {
    const auto lo = static_cast<std::uint32_t>(a < b ? a : b), hi = static_cast<std::uint32_t>(a < b ? b : a);
    return static_cast<std::uint64_t>(lo) << 32 | hi;
  }

  // The stamp stored for `key`, or nullptr.
  const std::uint32_t* find(std::uint64_t key) const {
    if (keys_.empty()) return nullptr;
    for (std::size_t i = home(key);; i = after(i)) {
      if (keys_[i] == kEmpty) return nullptr;
      if (keys_[i] == key) return &stamps_[i];
    }
  }

  // Stores `stamp` for `key`. When the table is full, it is rebuilt with the
  // entries for which keep(key, stamp) holds (the others are stale: dropped
  // instead of copied), at the size that leaves it half empty.
  template <class Keep>
  void assign(std::uint64_t key, std::uint32_t stamp, Keep keep) {
    if (5 * (size_ + 1) > 4 * keys_.size()) rebuild(keep);
    for (std::size_t i = home(key);; i = after(i)) {
      if (keys_[i] == key) {
        stamps_[i] = stamp;
        return;
      }
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        stamps_[i] = stamp;
        ++size_;
        return;
      }
    }
  }
  void assign(std::uint64_t key, std::uint32_t stamp) {
    assign(key, stamp, [](std::uint64_t, std::uint32_t) { return true; });
  }

  // Removes `key` if present; the entries after it in its probe run move
  // back so that no lookup stops early at the hole.
  void erase(std::uint64_t key) {
    if (keys_.empty()) return;
    std::size_t hole = home(key);
    while (keys_[hole] != key) {
      if (keys_[hole] == kEmpty) return;
      hole = after(hole);
    }
    for (std::size_t i = after(hole); keys_[i] != kEmpty; i = after(i)) {
      // The entry at i may fill the hole when its home is not cyclically in (hole, i].
      const std::size_t h = home(keys_[i]);
      const bool home_after_hole = hole <= i ? (hole < h && h <= i) : (hole < h || h <= i);
      if (home_after_hole) continue;
      keys_[hole] = keys_[i];
      stamps_[hole] = stamps_[i];
      hole = i;
    }
    keys_[hole] = kEmpty;
    --size_;
  }

  void clear() {
    keys_ = {};
    stamps_ = {};
    size_ = 0;
  }
  std::size_t size() const { return size_; }
  std::size_t bytes() const { return keys_.capacity() * sizeof(std::uint64_t) + stamps_.capacity() * sizeof(std::uint32_t); }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  std::size_t after(std::size_t i) const { return i + 1 == keys_.size() ? 0 : i + 1; }
  // The hash scaled to [0, size) by a multiplication (the table's size need
  // not be a power of two).
  std::size_t home(std::uint64_t key) const {
    const unsigned __int128 h = (key * 0x9E3779B97F4A7C15ull) ^ (key >> 29);
    return static_cast<std::size_t>((h * keys_.size()) >> 64);
  }
  template <class Keep>
  void rebuild(Keep keep) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] != kEmpty && keep(keys_[i], stamps_[i])) ++kept;
      else keys_[i] = kEmpty;
    const std::size_t n = std::max<std::size_t>(1024, 2 * (kept + 1));  // a load of at most 0.5
    std::vector<std::uint64_t> old_keys(n, kEmpty);
    std::vector<std::uint32_t> old_stamps(n, 0);
    old_keys.swap(keys_);
    old_stamps.swap(stamps_);
    size_ = 0;
    for (std::size_t i = 0; i < old_keys.size(); ++i)
      if (old_keys[i] != kEmpty) place(old_keys[i], old_stamps[i]);
  }
  // Inserts an entry known to be absent, with room for it.
  void place(std::uint64_t key, std::uint32_t stamp) {
    std::size_t i = home(key);
    while (keys_[i] != kEmpty) i = after(i);
    keys_[i] = key;
    stamps_[i] = stamp;
    ++size_;
  }

  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> stamps_;
  std::size_t size_ = 0;
};

}  // namespace anisurf::remesh
