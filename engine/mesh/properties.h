// Typed property arrays attached to mesh elements (vertices or triangles).
// A container keeps every array the same size as the element slots; arrays
// follow additions, deletions (free slots) and compact() renumbering.
#pragma once
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

#include "core/huge_pages.h"

namespace anisurf {

class BasePropertyArray {
 public:
  explicit BasePropertyArray(std::string name) : name_(std::move(name)) {}
  virtual ~BasePropertyArray() = default;
  virtual void resize(std::size_t n) = 0;
  virtual void reserve(std::size_t n) = 0;
  virtual void shrink_to_fit() = 0;
  virtual void reset(std::size_t i) = 0;  // back to the initial value
  // Keeps entries whose keep_map[i] >= 0, moved to keep_map[i]; new size n.
  virtual void compact(const std::vector<int>& keep_map, std::size_t n) = 0;
  virtual std::unique_ptr<BasePropertyArray> clone() const = 0;
  // An empty array of the same name, type and initial value.
  virtual std::unique_ptr<BasePropertyArray> clone_empty() const = 0;
  // Entry j takes entry i of `from` (pre: same type).
  virtual void copy_entry(const BasePropertyArray& from, std::size_t i, std::size_t j) = 0;
  // Grows to n entries (the new ones initial); entry to[i] takes entry i of
  // `from` (pre: same type), or the initial value when `from` is null, for
  // every to[i] >= 0. `from`'s storage is freed.
  virtual void absorb(BasePropertyArray* from, const std::vector<int>& to, std::size_t n) = 0;
  virtual const std::type_info& type() const = 0;
  virtual std::size_t size() const = 0;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

template <class T>
class PropertyArray final : public BasePropertyArray {
 public:
  PropertyArray(std::string name, T init) : BasePropertyArray(std::move(name)), init_(std::move(init)) {}
  void resize(std::size_t n) override { data_.resize(n, init_); }
  void reserve(std::size_t n) override { reserve_huge(data_, n); }
  void shrink_to_fit() override { data_.shrink_to_fit(); }
  void reset(std::size_t i) override { data_[i] = init_; }
  // In place (keep_map is increasing: entries only move down), so no second
  // copy of the array is ever alive.
  void compact(const std::vector<int>& keep_map, std::size_t n) override {
    for (std::size_t i = 0; i < keep_map.size() && i < data_.size(); ++i) {
      const auto to = static_cast<std::size_t>(keep_map[i]);
      if (keep_map[i] >= 0 && to != i) data_[to] = std::move(data_[i]);
    }
    data_.resize(n, init_);
  }
  std::unique_ptr<BasePropertyArray> clone() const override {
    auto p = std::make_unique<PropertyArray<T>>(name(), init_);
    p->data_ = data_;
    return p;
  }
  std::unique_ptr<BasePropertyArray> clone_empty() const override {
    return std::make_unique<PropertyArray<T>>(name(), init_);
  }
  void copy_entry(const BasePropertyArray& from, std::size_t i, std::size_t j) override {
    data_[j] = static_cast<const PropertyArray<T>&>(from).data_[i];
  }
  void absorb(BasePropertyArray* from, const std::vector<int>& to, std::size_t n) override {
    data_.resize(n, init_);
    auto* other = static_cast<PropertyArray<T>*>(from);
    for (std::size_t i = 0; i < to.size(); ++i) {
      if (to[i] < 0) continue;
      data_[static_cast<std::size_t>(to[i])] = other && i < other->data_.size() ? std::move(other->data_[i]) : init_;
    }
    if (other) std::vector<T>().swap(other->data_);
  }
  const std::type_info& type() const override { return typeid(T); }
  std::size_t size() const override { return data_.size(); }
  std::vector<T>& data() { return data_; }
  const std::vector<T>& data() const { return data_; }

 private:
  std::vector<T> data_;
  T init_;
};

// Handle to a property array; indexed by element handle (anything with .idx)
// or by raw index. Invalid when default constructed or when a lookup failed.
template <class T>
class Property {
 public:
  Property() = default;
  explicit Property(PropertyArray<T>* a) : array_(a) {}
  bool is_valid() const { return array_ != nullptr; }
  explicit operator bool() const { return is_valid(); }
  template <class Handle>
  T& operator[](Handle h) { return array_->data()[static_cast<std::size_t>(h.idx)]; }
  template <class Handle>
  const T& operator[](Handle h) const { return array_->data()[static_cast<std::size_t>(h.idx)]; }
  T& at(int i) { return array_->data()[static_cast<std::size_t>(i)]; }
  const T& at(int i) const { return array_->data()[static_cast<std::size_t>(i)]; }
  std::vector<T>& vector() { return array_->data(); }
  const std::vector<T>& vector() const { return array_->data(); }
  const std::string& name() const { return array_->name(); }

 private:
  PropertyArray<T>* array_ = nullptr;
};

class PropertyContainer {
 public:
  PropertyContainer() = default;
  PropertyContainer(const PropertyContainer& o) { *this = o; }
  PropertyContainer& operator=(const PropertyContainer& o) {
    if (this == &o) return *this;
    arrays_.clear();
    for (const auto& a : o.arrays_) arrays_.push_back(a->clone());
    size_ = o.size_;
    return *this;
  }
  PropertyContainer(PropertyContainer&&) noexcept = default;
  PropertyContainer& operator=(PropertyContainer&&) noexcept = default;

  // Adds a new array; throws if the name exists already.
  template <class T>
  Property<T> add(const std::string& name, const T& init = T()) {
    if (find(name)) throw std::logic_error("property '" + name + "' exists already");
    auto a = std::make_unique<PropertyArray<T>>(name, init);
    a->resize(size_);
    auto* raw = a.get();
    arrays_.push_back(std::move(a));
    return Property<T>(raw);
  }
  // Returns the array of that name and type, or an invalid handle.
  template <class T>
  Property<T> get(const std::string& name) const {
    BasePropertyArray* a = find(name);
    if (!a || a->type() != typeid(T)) return Property<T>();
    return Property<T>(static_cast<PropertyArray<T>*>(a));
  }
  template <class T>
  Property<T> get_or_add(const std::string& name, const T& init = T()) {
    auto p = get<T>(name);
    return p ? p : add<T>(name, init);
  }
  bool exists(const std::string& name) const { return find(name) != nullptr; }
  void remove(const std::string& name) {
    for (auto it = arrays_.begin(); it != arrays_.end(); ++it)
      if ((*it)->name() == name) { arrays_.erase(it); return; }
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& a : arrays_) out.push_back(a->name());
    return out;
  }
  std::size_t size() const { return size_; }
  void resize(std::size_t n) {
    size_ = n;
    for (auto& a : arrays_) a->resize(n);
  }
  void reserve(std::size_t n) {
    for (auto& a : arrays_) a->reserve(n);
  }
  void shrink_to_fit() {
    for (auto& a : arrays_) a->shrink_to_fit();
  }
  void push_back() { resize(size_ + 1); }
  void reset(std::size_t i) {
    for (auto& a : arrays_) a->reset(i);
  }
  void compact(const std::vector<int>& keep_map, std::size_t n) {
    for (auto& a : arrays_) a->compact(keep_map, n);
    size_ = n;
  }
  // Every array has the container's size (checked by validate()).
  bool sizes_consistent() const {
    for (const auto& a : arrays_)
      if (a->size() != size_) return false;
    return true;
  }
  void clear() { arrays_.clear(); size_ = 0; }
  // The same arrays (names, types, initial values), no entries.
  PropertyContainer empty_like() const {
    PropertyContainer c;
    for (const auto& a : arrays_) c.arrays_.push_back(a->clone_empty());
    return c;
  }
  // The arrays of this container and of `from` with the same name and type,
  // as (to, from) pairs: copy entries between containers of one layout.
  using ArrayPairs = std::vector<std::pair<BasePropertyArray*, const BasePropertyArray*>>;
  ArrayPairs pairs_with(const PropertyContainer& from) {
    ArrayPairs out;
    for (const auto& a : arrays_) {
      const BasePropertyArray* b = from.find(a->name());
      if (b && b->type() == a->type()) out.emplace_back(a.get(), b);
    }
    return out;
  }
  static void copy_entry(const ArrayPairs& pairs, std::size_t i, std::size_t j) {
    for (const auto& [to, from] : pairs) to->copy_entry(*from, i, j);
  }
  // Grows every array to n entries; entry to[i] takes entry i of `from`'s
  // array of the same name and type (the initial value where `from` has
  // none), one array at a time, each of `from`'s arrays freed once copied.
  void absorb(PropertyContainer& from, const std::vector<int>& to, std::size_t n) {
    for (auto& a : arrays_) {
      BasePropertyArray* b = from.find(a->name());
      a->absorb(b && b->type() == a->type() ? b : nullptr, to, n);
    }
    size_ = n;
  }

 private:
  BasePropertyArray* find(const std::string& name) const {
    for (const auto& a : arrays_)
      if (a->name() == name) return a.get();
    return nullptr;
  }
  std::vector<std::unique_ptr<BasePropertyArray>> arrays_;
  std::size_t size_ = 0;
};

// Per-vertex fields exchanged with .sol files.
enum class FieldKind { Scalar = 1, Vector = 2, Tensor = 3 };
// Up to 6 doubles: scalar (1), vector (2 or 3), symmetric tensor (3 in 2D, 6 in
// 3D, in the .sol file order m11 m12 m22 m13 m23 m33).
using FieldValue = std::array<double, 6>;
struct FieldInfo {
  std::string name;
  FieldKind kind = FieldKind::Scalar;
  int ncomp = 1;
};

}  // namespace anisurf
