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
#include <cstdint>
#include <memory>
#include <string>
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
  // Allocated slots, including deleted ones (loop bounds for raw iteration).
  int vertex_capacity() const { return static_cast<int>(vpos_.size()); }
  int triangle_capacity() const { return static_cast<int>(tv_.size() / 3); }
  bool has_garbage() const { return !free_vertices_.empty() || !free_triangles_.empty(); }
  bool is_deleted(Vertex v) const { return vcorner_[v.idx] == kDeletedMark; }
  bool is_deleted(Triangle t) const { return tv_[3 * t.idx] < 0; }
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
  Corner swing_ccw(Corner c) const;
  Corner swing_cw(Corner c) const;
  bool is_isolated(Vertex v) const { return vcorner_[v.idx] < 0; }
  bool is_boundary(Vertex v) const;
  int valence(Vertex v) const;
  // Corners of the fan of v, counter-clockwise from corner(v).
  std::vector<Corner> fan(Vertex v) const;
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
  void delete_triangle(Triangle t);  // unlinks its edges from neighbours, frees the slot
  // Frees a triangle slot without touching neighbours or vertices: for
  // operators that have already relinked everything around it.
  void release_triangle(Triangle t);
  void delete_vertex(Vertex v);      // pre: no live triangle uses v
  // Removes deleted slots; returns the renumbering. Properties follow.
  CompactMap compact();
  void clear();
  void reserve(int n_vertices, int n_triangles);

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

}  // namespace anisurf
