// A hash map from 64-bit keys to small values in one flat array: open
// addressing with linear probing (a Fibonacci hash of the key picks the
// first slot), erasure by backward shift (no tombstones). A lookup reads one
// or two cache lines where a node-based std::unordered_map follows a pointer
// per bucket and per node. The key ~0 (all bits set) is reserved for empty
// slots.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace anisurf {

template <class V>
class FlatMap64 {
 public:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  // The value of `key`, or nullptr. Valid until the next insertion or erasure.
  V* find(std::uint64_t key) {
    if (size_ == 0) return nullptr;
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      if (slots_[i].key == key) return &slots_[i].value;
      if (slots_[i].key == kEmpty) return nullptr;
    }
  }
  const V* find(std::uint64_t key) const { return const_cast<FlatMap64*>(this)->find(key); }

  // Sets the value of `key` (added when absent); returns it.
  V* insert_or_assign(std::uint64_t key, const V& value) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    std::size_t i = home(key);
    for (; slots_[i].key != kEmpty; i = (i + 1) & mask_)
      if (slots_[i].key == key) {
        slots_[i].value = value;
        return &slots_[i].value;
      }
    slots_[i] = {key, value};
    ++size_;
    return &slots_[i].value;
  }

  // Removes `key` if present; returns whether it was.
  bool erase(std::uint64_t key) {
    if (size_ == 0) return false;
    std::size_t i = home(key);
    for (; slots_[i].key != key; i = (i + 1) & mask_)
      if (slots_[i].key == kEmpty) return false;
    // Backward shift: each later entry of the run moves into the hole when
    // its home does not lie between the hole and itself (cyclically).
    for (std::size_t j = (i + 1) & mask_;; j = (j + 1) & mask_) {
      if (slots_[j].key == kEmpty) break;
      const std::size_t h = home(slots_[j].key);
      const bool stays = i <= j ? (i < h && h <= j) : (i < h || h <= j);
      if (stays) continue;
      slots_[i] = slots_[j];
      i = j;
    }
    slots_[i].key = kEmpty;
    --size_;
    return true;
  }

  // Empties the map; the storage is kept unless it is far larger than what
  // it held.
  void clear() {
    if (slots_.size() > 64 && slots_.size() > 8 * size_) {
      std::vector<Slot>().swap(slots_);
      mask_ = 0;
      shift_ = 64;
    } else {
      for (Slot& s : slots_) s.key = kEmpty;
    }
    size_ = 0;
  }
  void swap(FlatMap64& other) noexcept {
    slots_.swap(other.slots_);
    std::swap(size_, other.size_);
    std::swap(mask_, other.mask_);
    std::swap(shift_, other.shift_);
  }

 private:
  struct Slot {
    std::uint64_t key = kEmpty;
    V value{};
  };
  std::size_t home(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_) & mask_;
  }
  void grow() {
    const std::size_t capacity = slots_.empty() ? 16 : 2 * slots_.size();
    std::vector<Slot> old;
    old.swap(slots_);
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    size_ = 0;
    for (const Slot& s : old)
      if (s.key != kEmpty) insert_or_assign(s.key, s.value);
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
  int shift_ = 64;
};

}  // namespace anisurf
