// Integer references (Medit's "ref" of vertices, edges and triangles) per
// element slot. Most meshes have none, or only on a few elements: the array
// keeps no storage while every value is 0 and becomes a plain array at the
// first non-zero one (12 bytes per triangle saved for the edges alone).
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace anisurf {

class RefArray {
 public:
  std::size_t size() const { return size_; }
  int operator[](std::size_t i) const { return values_.empty() ? 0 : values_[i]; }
  // Pre: i < size().
  void set(std::size_t i, int r) {
    if (values_.empty()) {
      if (r == 0) return;
      values_.reserve(std::max(reserved_, size_));
      values_.assign(size_, 0);
    }
    values_[i] = r;
  }
  void push_back_zero() {
    ++size_;
    if (!values_.empty()) values_.push_back(0);
  }
  void resize(std::size_t n) {
    size_ = n;
    if (!values_.empty()) values_.resize(n, 0);
  }
  void reserve(std::size_t n) {
    reserved_ = n;
    if (!values_.empty()) values_.reserve(n);
  }
  void shrink_to_fit() { values_.shrink_to_fit(); }
  void clear() {
    size_ = 0;
    values_.clear();
  }
  bool stored() const { return !values_.empty(); }

 private:
  std::vector<int> values_;  // empty: every value is 0
  std::size_t size_ = 0;
  std::size_t reserved_ = 0;
};

}  // namespace anisurf
