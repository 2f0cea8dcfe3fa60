// Triangle surface mesh stored as a corner table.
//
// Per triangle t: three corners 3t, 3t+1, 3t+2, each with its vertex id and the
// opposite corner across the edge facing it (or -1 on a boundary / cut edge).
// Per vertex: position, one incident corner, tags and a reference. Deleted
// vertices and triangles go to free lists and are reused, so local operators
// (split, collapse, swap) never reallocate or renumber; compact() renumbers on
// demand and returns the permutations for attached data.
//
// Orientation: corners of a triangle are counter-clockwise seen from outside.
// The edge "of" corner c is the edge opposite to c, directed from
// vertex(next(c)) to vertex(prev(c)). Per-edge data (tags, reference) is stored
// on both corners of an interior edge and kept equal by the setters.
#pragma once
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <memory>
#include <string>
#include <type_traits>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "mesh/properties.h"
#include "mesh/ref_array.h"

namespace anisurf {

// Typed handles. An invalid handle has idx == -1.
struct Vertex {
  int idx = -1;
  constexpr Vertex() = default;
  constexpr explicit Vertex(int i) : idx(i) {}
  bool is_valid() const { return idx >= 0; }
  friend bool operator==(Vertex a, Vertex b) { return a.idx == b.idx; }
  friend bool operator!=(Vertex a, Vertex b) { return a.idx != b.idx; }
  friend bool operator<(Vertex a, Vertex b) { return a.idx < b.idx; }
};
struct Triangle {
  int idx = -1;
  constexpr Triangle() = default;
  constexpr explicit Triangle(int i) : idx(i) {}
  bool is_valid() const { return idx >= 0; }
  friend bool operator==(Triangle a, Triangle b) { return a.idx == b.idx; }
  friend bool operator!=(Triangle a, Triangle b) { return a.idx != b.idx; }
  friend bool operator<(Triangle a, Triangle b) { return a.idx < b.idx; }
};
struct Corner {
  int idx = -1;
  constexpr Corner() = default;
  constexpr explicit Corner(int i) : idx(i) {}
  bool is_valid() const { return idx >= 0; }
  friend bool operator==(Corner a, Corner b) { return a.idx == b.idx; }
  friend bool operator!=(Corner a, Corner b) { return a.idx != b.idx; }
  friend bool operator<(Corner a, Corner b) { return a.idx < b.idx; }
};

// Tags on vertices, edges and triangles (bit flags).
enum Tag : std::uint8_t {
  kNoTag = 0,
  kBoundary = 1 << 0,  // on an open boundary (derived from the connectivity)
  kRidge = 1 << 1,     // sharp feature (dihedral angle or file's Ridges)
  kCorner = 1 << 2,    // vertex where feature curves meet or turn sharply
  kRequired = 1 << 3,  // must not be moved or removed
  kListed = 1 << 4,    // edge listed in the file's Edges section (kept on output)
  kNonManifold = 1 << 5,  // edge that was cut because more than 2 triangles shared it
  // Vertex on the border of a region cut out for remeshing on its own
  // thread (remesh/partition.h): no new edge may join two of them (the
  // edge may exist outside the region).
  kFrozen = 1 << 6,
};

// Result of validate(): empty `errors` means every invariant holds.
struct ValidationReport {
  std::vector<std::string> errors;
  bool ok() const { return errors.empty(); }
  std::string summary(std::size_t max_lines = 10) const;
};

// Renumbering produced by compact(): old index -> new index (-1 if deleted).
struct CompactMap {
  std::vector<int> vertex;
  std::vector<int> triangle;
};
// Where absorb() put another mesh's slots (-1: a deleted slot).
using AbsorbMap = CompactMap;

class SurfaceMesh;

// --- ranges and circulators ----------------------------------------------------
//
// Light iterators (a mesh pointer and an index or a corner) used in range-for:
//   for (Vertex v : mesh.vertices()) ...
//   for (Corner c : mesh.fan_corners(v)) ...
// They end on a RangeEnd sentinel and allocate nothing.

// Sentinel that ends every range below.
struct RangeEnd {};

// Iterator over the live slots of one kind of element, in increasing index
// order: Vertex (live vertices), Triangle (live triangles) or Corner (edges:
// one corner per edge, the canonical one). Deleted slots are skipped when the
// iterator reaches them, and the end is read from the mesh at each comparison,
// so a loop over it visits what `for (i = 0; i < capacity; ++i) if (live(i))`
// visits, including slots added by the loop body.
template <class Handle>
class ElementIterator {
 public:
  using value_type = Handle;
  using difference_type = std::ptrdiff_t;
  using iterator_concept = std::forward_iterator_tag;

  ElementIterator() = default;
  // First live slot at or after idx.
  ElementIterator(const SurfaceMesh* mesh, int idx) : mesh_(mesh), idx_(idx) { skip_dead(); }
  Handle operator*() const { return Handle(idx_); }
  ElementIterator& operator++() {
    ++idx_;
    skip_dead();
    return *this;
  }
  ElementIterator operator++(int) {
    ElementIterator before = *this;
    ++*this;
    return before;
  }
  friend bool operator==(const ElementIterator& a, const ElementIterator& b) { return a.idx_ == b.idx_; }
  friend bool operator==(const ElementIterator& it, RangeEnd) { return it.idx_ >= it.slot_count(); }

 private:
  int slot_count() const;  // current number of slots of this kind
  bool is_live() const;    // slot idx_ holds a live element
  void skip_dead() {
    while (idx_ < slot_count() && !is_live()) ++idx_;
  }
  const SurfaceMesh* mesh_ = nullptr;
  int idx_ = 0;
};

// Circulator over the corners of a vertex fan, counter-clockwise from a start
// corner; it ends when the swing reaches a boundary (invalid corner) or comes
// back to the start (see SurfaceMesh::fan_corners).
class FanCornerIterator {
 public:
  using value_type = Corner;
  using difference_type = std::ptrdiff_t;
  using iterator_concept = std::forward_iterator_tag;

  FanCornerIterator() = default;
  FanCornerIterator(const SurfaceMesh* mesh, Corner start) : mesh_(mesh), start_(start), current_(start) {}
  Corner operator*() const { return current_; }
  inline FanCornerIterator& operator++();
  FanCornerIterator operator++(int) {
    FanCornerIterator before = *this;
    ++*this;
    return before;
  }
  friend bool operator==(const FanCornerIterator& a, const FanCornerIterator& b) {
    return a.current_ == b.current_ && a.visited_ == b.visited_;
  }
  friend bool operator==(const FanCornerIterator& it, RangeEnd) { return !it.current_.is_valid(); }

 private:
  const SurfaceMesh* mesh_ = nullptr;
  Corner start_;
  Corner current_;            // invalid once the fan is done
  std::size_t visited_ = 0;   // corners passed so far (guards a corrupt fan)
};

// Circulator over the one-ring neighbours of a vertex: vertex(next(c)) for
// each corner c of the fan, then, when the vertex is on a boundary, the
// vertex closing the open fan, vertex(prev(last corner)) (see
// SurfaceMesh::ring_vertices).
class RingVertexIterator {
 public:
  using value_type = Vertex;
  using difference_type = std::ptrdiff_t;
  using iterator_concept = std::forward_iterator_tag;

  RingVertexIterator() = default;
  // closes_fan: the fan is open (the vertex is on a boundary), so the ring
  // ends with the vertex after the last fan corner.
  RingVertexIterator(const SurfaceMesh* mesh, Corner start, bool closes_fan)
      : fan_(mesh, start), mesh_(mesh), closes_fan_(closes_fan) {}
  inline Vertex operator*() const;
  RingVertexIterator& operator++() {
    if (at_closing_) {
      at_closing_ = false;
      return *this;
    }
    last_ = *fan_;
    ++fan_;
    at_closing_ = closes_fan_ && fan_ == RangeEnd{};
    return *this;
  }
  RingVertexIterator operator++(int) {
    RingVertexIterator before = *this;
    ++*this;
    return before;
  }
  friend bool operator==(const RingVertexIterator& a, const RingVertexIterator& b) {
    return a.fan_ == b.fan_ && a.at_closing_ == b.at_closing_;
  }
  friend bool operator==(const RingVertexIterator& it, RangeEnd) { return it.fan_ == RangeEnd{} && !it.at_closing_; }

 private:
  FanCornerIterator fan_;
  const SurfaceMesh* mesh_ = nullptr;
  Corner last_;               // the fan corner before the closing vertex
  bool closes_fan_ = false;
  bool at_closing_ = false;   // yielding the closing vertex of an open fan
};

// A range for range-for (and std::ranges algorithms): a first iterator and
// the RangeEnd sentinel.
template <class Iterator>
class HandleRange {
 public:
  HandleRange() = default;
  explicit HandleRange(Iterator first) : first_(first) {}
  Iterator begin() const { return first_; }
  RangeEnd end() const { return {}; }
  bool empty() const { return first_ == RangeEnd{}; }

 private:
  Iterator first_;
};

using VertexRange = HandleRange<ElementIterator<Vertex>>;
using TriangleRange = HandleRange<ElementIterator<Triangle>>;
using EdgeRange = HandleRange<ElementIterator<Corner>>;
using FanCornerRange = HandleRange<FanCornerIterator>;
using RingVertexRange = HandleRange<RingVertexIterator>;

class SurfaceMesh {
 public:
  SurfaceMesh();
  SurfaceMesh(const SurfaceMesh&);
  SurfaceMesh& operator=(const SurfaceMesh&);
  SurfaceMesh(SurfaceMesh&&) noexcept = default;
  SurfaceMesh& operator=(SurfaceMesh&&) noexcept = default;
  ~SurfaceMesh() = default;

  // --- sizes -------------------------------------------------------------
  int n_vertices() const { return static_cast<int>(vpos_.size()) - static_cast<int>(free_vertices_.size()); }
  int n_triangles() const { return static_cast<int>(tv_.size() / 3) - static_cast<int>(free_triangles_.size()); }
  // Allocated slots, including deleted ones: sizes of arrays indexed by slot.
  int vertex_capacity() const { return static_cast<int>(vpos_.size()); }
  int triangle_capacity() const { return static_cast<int>(tv_.size() / 3); }
  // Corner slots (3 per triangle slot, deleted ones included).
  int corner_capacity() const { return static_cast<int>(tv_.size()); }
  bool has_garbage() const { return !free_vertices_.empty() || !free_triangles_.empty(); }
  bool is_deleted(Vertex v) const { return vcorner_[v.idx] == kDeletedMark; }
  bool is_deleted(Triangle t) const { return tv_[3 * t.idx] < 0; }

  // --- iteration over live elements (increasing index order) ---------------
  // Live vertices; cheap to create, allocates nothing.
  VertexRange vertices() const { return VertexRange(ElementIterator<Vertex>(this, 0)); }
  // Live triangles.
  TriangleRange triangles() const { return TriangleRange(ElementIterator<Triangle>(this, 0)); }
  // Edges of live triangles, each once, named by its canonical corner
  // (canonical(c) == c: the opposite corner is invalid or has a larger index).
  EdgeRange edges() const { return EdgeRange(ElementIterator<Corner>(this, 0)); }
  // True if c is the corner that names its edge in edges(): its triangle is
  // live and canonical(c) == c.
  bool is_edge_corner(Corner c) const {
    return tv_[3 * (c.idx / 3)] >= 0 && (to_[c.idx] < 0 || to_[c.idx] > c.idx);
  }

  // Spatial dimension of the source (2 for planar Medit files, else 3).
  int dimension() const { return dimension_; }
  void set_dimension(int d) { dimension_ = d; }

  // --- corner arithmetic (the one place for index tricks) -----------------
  static Triangle triangle(Corner c) { return Triangle(c.idx / 3); }
  static Corner corner(Triangle t, int k) { return Corner(3 * t.idx + k); }
  static int local_index(Corner c) { return c.idx % 3; }
  static Corner next(Corner c) { return Corner(c.idx % 3 == 2 ? c.idx - 2 : c.idx + 1); }
  static Corner prev(Corner c) { return Corner(c.idx % 3 == 0 ? c.idx + 2 : c.idx - 1); }

  Vertex vertex(Corner c) const { return Vertex(tv_[c.idx]); }
  Vertex vertex(Triangle t, int k) const { return Vertex(tv_[3 * t.idx + k]); }
  // The 3 vertex ids of slot t (the first one negative when deleted): the
  // corner table itself, for readers that index it in bulk (locate/).
  const int* triangle_vertices(Triangle t) const { return tv_.data() + 3 * static_cast<std::size_t>(t.idx); }
  // Corner across the edge opposite c, or invalid on a boundary edge.
  Corner opposite(Corner c) const { return Corner(to_[c.idx]); }
  bool is_boundary_edge(Corner c) const { return to_[c.idx] < 0; }
  // Endpoints of the edge opposite c (directed as in c's triangle).
  Vertex edge_from(Corner c) const { return vertex(next(c)); }
  Vertex edge_to(Corner c) const { return vertex(prev(c)); }

  // One incident corner of v. For a boundary vertex it is the most clockwise
  // one, so that a counter-clockwise swing from it visits the whole fan.
  Corner corner(Vertex v) const { return Corner(vcorner_[v.idx]); }
  // Corner at the same vertex in the next triangle counter-clockwise / clockwise
  // (invalid when the fan ends on a boundary).
  Corner swing_ccw(Corner c) const {
    // The triangle counter-clockwise of c's triangle around v lies across the
    // edge (prev(c) -> v), which is the edge opposite next(c).
    const int o = to_[next(c).idx];
    return o < 0 ? Corner() : next(Corner(o));
  }
  Corner swing_cw(Corner c) const {
    // Across the edge (v -> next(c)), opposite prev(c).
    const int o = to_[prev(c).idx];
    return o < 0 ? Corner() : prev(Corner(o));
  }
  bool is_isolated(Vertex v) const { return vcorner_[v.idx] < 0; }
  // True if v's fan is open: the edge clockwise of corner(v) is a boundary.
  bool is_boundary(Vertex v) const {
    const int c = vcorner_[v.idx];
    return c >= 0 && to_[prev(Corner(c)).idx] < 0;
  }
  int valence(Vertex v) const;
  // Corners of the fan of v, counter-clockwise from corner(v), in a vector
  // (fan_corners(v) visits the same corners without allocating).
  std::vector<Corner> fan(Vertex v) const;
  // Circulator over the corners of the fan of v, counter-clockwise from
  // corner(v): the corners of fan(v), in the same order. An open fan ends at
  // the boundary; empty for an isolated or deleted vertex.
  FanCornerRange fan_corners(Vertex v) const { return FanCornerRange(FanCornerIterator(this, corner(v))); }
  // Circulator over the neighbours of v, counter-clockwise: vertex(next(c))
  // for each corner c of fan_corners(v), then, when v is on a boundary, the
  // vertex closing the open fan (the same vertices as one_ring(mesh, v)).
  RingVertexRange ring_vertices(Vertex v) const {
    return RingVertexRange(RingVertexIterator(this, corner(v), is_boundary(v)));
  }
  // Corner c in triangle t whose vertex is v (invalid if v is not in t).
  Corner corner_of(Triangle t, Vertex v) const;
  // Corner whose opposite edge is the directed edge a->b, searched in the fan of a.
  Corner find_edge(Vertex a, Vertex b) const;
  // Canonical corner of the edge opposite c: the smaller of c and opposite(c).
  Corner canonical(Corner c) const {
    int o = to_[c.idx];
    return (o >= 0 && o < c.idx) ? Corner(o) : c;
  }

  // --- geometry -----------------------------------------------------------
  const Vec3& position(Vertex v) const { return vpos_[v.idx]; }
  Vec3& position(Vertex v) { return vpos_[v.idx]; }
  Vec3 triangle_normal(Triangle t) const;  // not normalised: twice the area
  double triangle_area(Triangle t) const;
  BBox bbox() const;

  // --- tags and references -------------------------------------------------
  std::uint8_t vertex_tags(Vertex v) const { return vtag_[v.idx]; }
  void set_vertex_tags(Vertex v, std::uint8_t t) { vtag_[v.idx] = t; }
  void add_vertex_tag(Vertex v, Tag t) { vtag_[v.idx] |= t; }
  void remove_vertex_tag(Vertex v, Tag t) { vtag_[v.idx] &= static_cast<std::uint8_t>(~t); }
  bool has_tag(Vertex v, Tag t) const { return (vtag_[v.idx] & t) != 0; }
  int vertex_ref(Vertex v) const { return vref_[v.idx]; }
  // False while every vertex (triangle) reference is 0 (none stored).
  bool has_vertex_refs() const { return vref_.stored(); }
  bool has_triangle_refs() const { return tref_.stored(); }
  void set_vertex_ref(Vertex v, int r) { vref_.set(static_cast<std::size_t>(v.idx), r); }

  std::uint8_t edge_tags(Corner c) const { return etag_[c.idx]; }
  void set_edge_tags(Corner c, std::uint8_t t);
  void add_edge_tag(Corner c, Tag t) { set_edge_tags(c, etag_[c.idx] | t); }
  void remove_edge_tag(Corner c, Tag t) { set_edge_tags(c, etag_[c.idx] & static_cast<std::uint8_t>(~t)); }
  bool has_tag(Corner c, Tag t) const { return (etag_[c.idx] & t) != 0; }
  int edge_ref(Corner c) const { return eref_[c.idx]; }
  void set_edge_ref(Corner c, int r);

  std::uint8_t triangle_tags(Triangle t) const { return ttag_[t.idx]; }
  void set_triangle_tags(Triangle t, std::uint8_t g) { ttag_[t.idx] = g; }
  bool has_tag(Triangle t, Tag g) const { return (ttag_[t.idx] & g) != 0; }
  int triangle_ref(Triangle t) const { return tref_[t.idx]; }
  void set_triangle_ref(Triangle t, int r) { tref_.set(static_cast<std::size_t>(t.idx), r); }

  // Recompute kBoundary on edges and vertices from the connectivity.
  void update_boundary_tags();

  // --- construction and local mutation ------------------------------------
  // Adds a vertex (reusing a free slot if any). Its properties are default.
  Vertex add_vertex(const Vec3& p);
  // Adds a triangle a,b,c (counter-clockwise) and links it to its neighbours
  // through edges that are currently boundary edges with the reverse direction.
  // Pre: a, b, c live and distinct; the result stays manifold.
  Triangle add_triangle(Vertex a, Vertex b, Vertex c);
  // Low-level: set the vertex ids of a triangle slot and the opposite links;
  // the caller restores the invariants (used by builders and operators).
  void set_corner_vertex(Corner c, Vertex v) { tv_[c.idx] = v.idx; }
  void link(Corner a, Corner b);  // makes a and b opposite (b may be invalid)
  void set_vertex_corner(Vertex v, Corner c) { vcorner_[v.idx] = c.idx; }
  // Chooses corner(v) as the start of its fan (the boundary-most one).
  void update_vertex_corner(Vertex v);
  Triangle allocate_triangle();  // uninitialised slot, reused from the free list
  // Low-level, for builders: appends the vertices at `p` (default
  // properties, no corner) and the triangles `t` (vertex ids, no links), in
  // order, after every slot in use, each array grown once. Returns the first
  // new slot. Pre: no free slot of that kind (a fresh or compacted mesh).
  int append_vertices(std::span<const Vec3> p);
  int append_triangles(std::span<const std::array<int, 3>> t);
  void delete_triangle(Triangle t);  // unlinks its edges from neighbours, frees the slot
  // Frees a triangle slot without touching neighbours or vertices: for
  // operators that have already relinked everything around it.
  void release_triangle(Triangle t);
  void delete_vertex(Vertex v);      // pre: no live triangle uses v
  // Removes deleted slots; returns the renumbering. Properties follow.
  CompactMap compact();
  // Frees the opposite links (12 bytes a triangle) and, when no vertex slot
  // is free, the vertex corners (4 bytes a vertex) of a mesh that only
  // waits, when restore_links() finds the links all again from the
  // triangles alone: a corner's opposite is the corner whose edge runs the
  // other way, so no two edges around a vertex may run to the same vertex in
  // the same direction, nor a border edge have its reverse (a slit whose two
  // sides share their ends keeps its links). Checked on the fans, with no
  // copy. Returns whether they were freed. A finished region holds less
  // while the others run. Until restore_links(), nothing else may use the
  // mesh; after it, the links are the same and each vertex corner is one of
  // the vertex's fan (the most clockwise on a border, as always).
  bool release_links();
  void restore_links();
  // Frees the links for good, of a mesh given away whose triangles are
  // still to be read (to_mesh_data): nothing may walk it afterwards.
  void discard_links() { std::vector<int>().swap(to_); }
  bool links_released() const { return to_.size() != tv_.size(); }
  // True when restore_links() would give back exactly the links there are.
  bool links_restorable() const;
  // Moves the live elements of `part` into this mesh (the regions of a
  // parallel pass pasted back): vertex v of part is vertex existing[v] of
  // this mesh when that is >= 0 (its data here stays), else a new one, which
  // takes v's position, tags, reference, corner and properties; every live
  // triangle is a new one, with its tags, references, properties and the
  // links between part's triangles (part's open corners stay open, for the
  // caller to link). Free slots are used first. The copy goes one array at
  // a time, each of part's arrays freed once copied, so the two meshes never
  // hold two copies of the pasted elements at once. The caller restores the
  // fans of the existing vertices.
  AbsorbMap absorb(SurfaceMesh&& part, const std::vector<int>& existing);
  // A mesh with no elements and this one's layout: dimension, fields, and
  // property arrays of the same names and types (for copying elements
  // between the two: PropertyContainer::pairs_with).
  SurfaceMesh empty_like() const;
  void clear();
  void reserve(int n_vertices, int n_triangles);
  // Moves the positions out (one per vertex slot) and leaves the mesh empty,
  // its memory freed: for a conversion that consumes the mesh
  // (to_mesh_data(SurfaceMesh&&)).
  std::vector<Vec3> release_positions();
  // Gives back the memory reserved beyond the slots in use, one array at a
  // time (each copy is alive only while its array is).
  void shrink_to_fit();

  // Checks every invariant: ids in range and live, no degenerate triangle,
  // opposite links symmetric with reversed endpoints (consistent orientation),
  // each vertex fan manifold and complete, edge data equal on both sides,
  // free lists sound, property arrays sized.
  ValidationReport validate() const;

  // --- attached data ---------------------------------------------------------
  PropertyContainer& vertex_properties() { return vprops_; }
  const PropertyContainer& vertex_properties() const { return vprops_; }
  PropertyContainer& triangle_properties() { return tprops_; }
  const PropertyContainer& triangle_properties() const { return tprops_; }

  template <class T>
  Property<T> add_vertex_property(const std::string& name, const T& init = T()) {
    return vprops_.add<T>(name, init);
  }
  template <class T>
  Property<T> get_vertex_property(const std::string& name) const {
    return vprops_.get<T>(name);
  }
  template <class T>
  Property<T> vertex_property(const std::string& name, const T& init = T()) {
    return vprops_.get_or_add<T>(name, init);
  }
  template <class T>
  Property<T> add_triangle_property(const std::string& name, const T& init = T()) {
    return tprops_.add<T>(name, init);
  }
  template <class T>
  Property<T> get_triangle_property(const std::string& name) const {
    return tprops_.get<T>(name);
  }

  // Named per-vertex fields read from / written to .sol files (scalar, vector,
  // symmetric tensor); stored as vertex property arrays of fixed stride.
  std::vector<FieldInfo>& fields() { return fields_; }
  const std::vector<FieldInfo>& fields() const { return fields_; }
  // Adds a field of `ncomp` doubles per vertex; returns its property.
  Property<FieldValue> add_field(const std::string& name, FieldKind kind, int ncomp);
  Property<FieldValue> get_field(const std::string& name) const;
  void remove_field(const std::string& name);  // no-op when absent

  static constexpr int kDeletedMark = -2;

 private:
  void push_vertex_slot();
  // The links found again from the triangles (restore_links).
  void rebuild_links();
  // A corner of each vertex's fan, the most clockwise on a border.
  void rebuild_vertex_corners();
  void push_triangle_slot();

  // vertices
  std::vector<Vec3> vpos_;
  std::vector<int> vcorner_;   // -1 isolated, kDeletedMark deleted
  std::vector<std::uint8_t> vtag_;
  RefArray vref_;
  // triangles / corners
  std::vector<int> tv_;        // 3 per triangle; tv_[3t] == -1 marks a deleted slot
  std::vector<int> to_;        // opposite corner or -1
  std::vector<std::uint8_t> etag_;  // per corner: tags of its opposite edge
  RefArray eref_;           // per corner: reference of its opposite edge
  std::vector<std::uint8_t> ttag_;
  RefArray tref_;
  // free lists
  std::vector<int> free_vertices_;
  std::vector<int> free_triangles_;
  // attached data
  PropertyContainer vprops_;
  PropertyContainer tprops_;
  std::vector<FieldInfo> fields_;
  int dimension_ = 3;
};

// --- inline definitions of the iterators (need the complete SurfaceMesh) -----

template <class Handle>
int ElementIterator<Handle>::slot_count() const {
  if constexpr (std::is_same_v<Handle, Vertex>) return mesh_->vertex_capacity();
  else if constexpr (std::is_same_v<Handle, Triangle>) return mesh_->triangle_capacity();
  else return mesh_->corner_capacity();
}

template <class Handle>
bool ElementIterator<Handle>::is_live() const {
  if constexpr (std::is_same_v<Handle, Corner>) return mesh_->is_edge_corner(Corner(idx_));
  else return !mesh_->is_deleted(Handle(idx_));
}

inline FanCornerIterator& FanCornerIterator::operator++() {
  // Stops at a boundary, back at the start, or after more corners than the
  // mesh has (a corrupt fan).
  ++visited_;
  const Corner n = mesh_->swing_ccw(current_);
  const bool more = n.is_valid() && n != start_ && visited_ <= static_cast<std::size_t>(mesh_->corner_capacity());
  current_ = more ? n : Corner();
  return *this;
}

inline Vertex RingVertexIterator::operator*() const {
  return at_closing_ ? mesh_->vertex(SurfaceMesh::prev(last_)) : mesh_->vertex(SurfaceMesh::next(*fan_));
}

}  // namespace anisurf
