#include "mesh/surface_mesh.h"

#include "core/huge_pages.h"

#include <algorithm>
#include <cassert>
#include <sstream>

namespace anisurf {

std::string ValidationReport::summary(std::size_t max_lines) const {
  std::ostringstream ss;
  for (std::size_t i = 0; i < errors.size() && i < max_lines; ++i) ss << errors[i] << "\n";
  if (errors.size() > max_lines) ss << "... and " << errors.size() - max_lines << " more\n";
  return ss.str();
}

SurfaceMesh::SurfaceMesh() = default;
SurfaceMesh::SurfaceMesh(const SurfaceMesh&) = default;
SurfaceMesh& SurfaceMesh::operator=(const SurfaceMesh&) = default;

// --- navigation ---------------------------------------------------------------

std::vector<Corner> SurfaceMesh::fan(Vertex v) const {
  std::vector<Corner> out;
  if (!corner(v).is_valid()) return out;
  out.reserve(8);  // most fans: no reallocation
  for (Corner c : fan_corners(v)) out.push_back(c);
  return out;
}

int SurfaceMesh::valence(Vertex v) const {
  // Number of distinct neighbours: triangles in the fan, plus one on a boundary.
  int n = 0;
  for (Corner c : fan_corners(v)) {
    (void)c;
    ++n;
  }
  return is_boundary(v) ? n + 1 : n;
}

Corner SurfaceMesh::corner_of(Triangle t, Vertex v) const {
  for (int k = 0; k < 3; ++k)
    if (tv_[3 * t.idx + k] == v.idx) return Corner(3 * t.idx + k);
  return Corner();
}

Corner SurfaceMesh::find_edge(Vertex a, Vertex b) const {
  // The directed edge a->b is opposite prev(c) for the corner c at a whose
  // next vertex is b.
  for (Corner c : fan_corners(a))
    if (vertex(next(c)) == b) return prev(c);
  return Corner();
}

// --- geometry -----------------------------------------------------------------

Vec3 SurfaceMesh::triangle_normal(Triangle t) const {
  const Vec3& a = vpos_[tv_[3 * t.idx]];
  const Vec3& b = vpos_[tv_[3 * t.idx + 1]];
  const Vec3& c = vpos_[tv_[3 * t.idx + 2]];
  return cross(b - a, c - a);
}

double SurfaceMesh::triangle_area(Triangle t) const { return 0.5 * norm(triangle_normal(t)); }

BBox SurfaceMesh::bbox() const {
  BBox b;
  for (Vertex v : vertices()) b.add(position(v));
  return b;
}

// --- tags -----------------------------------------------------------------------

void SurfaceMesh::set_edge_tags(Corner c, std::uint8_t t) {
  etag_[c.idx] = t;
  int o = to_[c.idx];
  if (o >= 0) etag_[o] = t;
}

void SurfaceMesh::set_edge_ref(Corner c, int r) {
  eref_.set(c.idx, r);
  int o = to_[c.idx];
  if (o >= 0) eref_.set(o, r);
}

void SurfaceMesh::update_boundary_tags() {
  for (Vertex v : vertices()) remove_vertex_tag(v, kBoundary);
  for (Triangle t : triangles()) {
    for (int k = 0; k < 3; ++k) {
      const int c = corner(t, k).idx;
      if (to_[c] < 0) {
        etag_[c] |= kBoundary;
        vtag_[tv_[next(Corner(c)).idx]] |= kBoundary;
        vtag_[tv_[prev(Corner(c)).idx]] |= kBoundary;
      } else {
        etag_[c] &= static_cast<std::uint8_t>(~kBoundary);
      }
    }
  }
}

// --- mutation -------------------------------------------------------------------

void SurfaceMesh::push_vertex_slot() {
  vpos_.emplace_back();
  vcorner_.push_back(-1);
  vtag_.push_back(0);
  vref_.push_back_zero();
  vprops_.push_back();
}

void SurfaceMesh::push_triangle_slot() {
  for (int k = 0; k < 3; ++k) {
    tv_.push_back(-1);
    to_.push_back(-1);
    etag_.push_back(0);
    eref_.push_back_zero();
  }
  ttag_.push_back(0);
  tref_.push_back_zero();
  tprops_.push_back();
}

Vertex SurfaceMesh::add_vertex(const Vec3& p) {
  int v;
  if (!free_vertices_.empty()) {
    v = free_vertices_.back();
    free_vertices_.pop_back();
    vprops_.reset(static_cast<std::size_t>(v));
  } else {
    v = vertex_capacity();
    push_vertex_slot();
  }
  vpos_[v] = p;
  vcorner_[v] = -1;
  vtag_[v] = 0;
  vref_.set(v, 0);
  return Vertex(v);
}

Triangle SurfaceMesh::allocate_triangle() {
  int t;
  if (!free_triangles_.empty()) {
    t = free_triangles_.back();
    free_triangles_.pop_back();
    tprops_.reset(static_cast<std::size_t>(t));
  } else {
    t = triangle_capacity();
    push_triangle_slot();
  }
  for (int k = 0; k < 3; ++k) {
    tv_[3 * t + k] = -1;
    to_[3 * t + k] = -1;
    etag_[3 * t + k] = 0;
    eref_.set(3 * t + k, 0);
  }
  ttag_[t] = 0;
  tref_.set(t, 0);
  return Triangle(t);
}

int SurfaceMesh::append_vertices(std::span<const Vec3> p) {
  assert(free_vertices_.empty());
  const std::size_t first = vpos_.size(), n = first + p.size();
  vpos_.insert(vpos_.end(), p.begin(), p.end());
  vcorner_.resize(n, -1);
  vtag_.resize(n, 0);
  vref_.resize(n);
  vprops_.resize(n);
  return static_cast<int>(first);
}

int SurfaceMesh::append_triangles(std::span<const std::array<int, 3>> t) {
  assert(free_triangles_.empty());
  const std::size_t first = tv_.size() / 3, n = first + t.size();
  for (const std::array<int, 3>& v : t) tv_.insert(tv_.end(), v.begin(), v.end());
  to_.resize(3 * n, -1);
  etag_.resize(3 * n, 0);
  eref_.resize(3 * n);
  ttag_.resize(n, 0);
  tref_.resize(n);
  tprops_.resize(n);
  return static_cast<int>(first);
}

void SurfaceMesh::link(Corner a, Corner b) {
  to_[a.idx] = b.idx;
  if (b.is_valid()) to_[b.idx] = a.idx;
}

void SurfaceMesh::update_vertex_corner(Vertex v) {
  int c0 = vcorner_[v.idx];
  if (c0 < 0) return;
  // Walk clockwise until the boundary (or back to the start).
  Corner start(c0), c = start;
  std::size_t guard = 0;
  while (true) {
    Corner n = swing_cw(c);
    if (!n.is_valid() || n == start || ++guard > tv_.size()) break;
    c = n;
  }
  vcorner_[v.idx] = c.idx;
}

Triangle SurfaceMesh::add_triangle(Vertex a, Vertex b, Vertex c) {
  assert(a != b && b != c && a != c);
  // Find the neighbours first (before this triangle's own corners exist).
  const Vertex vs[3] = {a, b, c};
  Corner across[3];
  for (int k = 0; k < 3; ++k) {
    // Edge opposite corner k goes vs[k+1] -> vs[k+2]; its twin is vs[k+2] -> vs[k+1].
    Vertex from = vs[(k + 2) % 3], to = vs[(k + 1) % 3];
    Corner e = is_isolated(from) ? Corner() : find_edge(from, to);
    across[k] = (e.is_valid() && to_[e.idx] < 0) ? e : Corner();
  }
  Triangle t = allocate_triangle();
  for (int k = 0; k < 3; ++k) tv_[3 * t.idx + k] = vs[k].idx;
  for (int k = 0; k < 3; ++k)
    if (across[k].is_valid()) {
      link(corner(t, k), across[k]);
      etag_[3 * t.idx + k] = etag_[across[k].idx];
      eref_.set(3 * t.idx + k, eref_[across[k].idx]);
    }
  for (int k = 0; k < 3; ++k) {
    if (vcorner_[vs[k].idx] < 0) vcorner_[vs[k].idx] = 3 * t.idx + k;
    update_vertex_corner(vs[k]);
  }
  return t;
}

void SurfaceMesh::delete_triangle(Triangle t) {
  if (is_deleted(t)) return;
  int verts[3];
  int replacement[3];
  for (int k = 0; k < 3; ++k) {
    Corner c = corner(t, k);
    verts[k] = tv_[c.idx];
    // Another corner at the same vertex, found before the links are cut.
    Corner other = swing_ccw(c);
    if (!other.is_valid()) other = swing_cw(c);
    replacement[k] = other.is_valid() ? other.idx : -1;
  }
  for (int k = 0; k < 3; ++k) {
    int c = 3 * t.idx + k;
    if (to_[c] >= 0) to_[to_[c]] = -1;
    to_[c] = -1;
    tv_[c] = -1;
    etag_[c] = 0;
    eref_.set(c, 0);
  }
  ttag_[t.idx] = 0;
  tref_.set(t.idx, 0);
  free_triangles_.push_back(t.idx);
  for (int k = 0; k < 3; ++k) {
    int v = verts[k];
    if (vcorner_[v] >= 0 && vcorner_[v] / 3 == t.idx) vcorner_[v] = replacement[k];
    update_vertex_corner(Vertex(v));
  }
}

void SurfaceMesh::release_triangle(Triangle t) {
  for (int k = 0; k < 3; ++k) {
    tv_[3 * t.idx + k] = -1;
    to_[3 * t.idx + k] = -1;
    etag_[3 * t.idx + k] = 0;
    eref_.set(3 * t.idx + k, 0);
  }
  ttag_[t.idx] = 0;
  tref_.set(t.idx, 0);
  free_triangles_.push_back(t.idx);
}

void SurfaceMesh::delete_vertex(Vertex v) {
  if (is_deleted(v)) return;
  vcorner_[v.idx] = kDeletedMark;
  vtag_[v.idx] = 0;
  free_vertices_.push_back(v.idx);
}

CompactMap SurfaceMesh::compact() {
  CompactMap map;
  map.vertex.assign(vpos_.size(), -1);
  map.triangle.assign(tv_.size() / 3, -1);
  int nv = 0, nt = 0;
  for (std::size_t v = 0; v < vpos_.size(); ++v)
    if (vcorner_[v] != kDeletedMark) map.vertex[v] = nv++;
  for (std::size_t t = 0; t < tv_.size() / 3; ++t)
    if (tv_[3 * t] >= 0) map.triangle[t] = nt++;

  auto corner_map = [&](int c) { return c < 0 ? c : 3 * map.triangle[c / 3] + c % 3; };

  // In place: the maps are increasing, so every slot moves down (or stays)
  // and is read before anything is written over it.
  for (std::size_t v = 0; v < vpos_.size(); ++v) {
    const int n = map.vertex[v];
    if (n < 0) continue;
    vpos_[n] = vpos_[v];
    vcorner_[n] = corner_map(vcorner_[v]);
    vtag_[n] = vtag_[v];
    vref_.set(n, vref_[v]);
  }
  for (std::size_t t = 0; t < tv_.size() / 3; ++t) {
    const int n = map.triangle[t];
    if (n < 0) continue;
    for (int k = 0; k < 3; ++k) {
      tv_[3 * n + k] = map.vertex[tv_[3 * t + k]];
      to_[3 * n + k] = corner_map(to_[3 * t + k]);
      etag_[3 * n + k] = etag_[3 * t + k];
      eref_.set(3 * n + k, eref_[3 * t + k]);
    }
    ttag_[n] = ttag_[t];
    tref_.set(n, tref_[t]);
  }
  vpos_.resize(nv);
  vcorner_.resize(nv);
  vtag_.resize(nv);
  vref_.resize(nv);
  tv_.resize(3 * nt);
  to_.resize(3 * nt);
  etag_.resize(3 * nt);
  eref_.resize(3 * nt);
  ttag_.resize(nt);
  tref_.resize(nt);
  free_vertices_.clear();
  free_triangles_.clear();
  vprops_.compact(map.vertex, static_cast<std::size_t>(nv));
  tprops_.compact(map.triangle, static_cast<std::size_t>(nt));
  return map;
}

namespace {

// into[to[i]] = f(from[i]) for every to[i] >= 0, into grown to n entries
// first; from's storage is freed.
template <class T, class F>
void scatter_and_free(std::vector<T>& into, std::size_t n, std::vector<T>& from, const std::vector<int>& to, F&& f) {
  into.resize(n);
  for (std::size_t i = 0; i < to.size(); ++i)
    if (to[i] >= 0) into[static_cast<std::size_t>(to[i])] = f(from[i]);
  std::vector<T>().swap(from);
}

void scatter_and_free(RefArray& into, std::size_t n, RefArray& from, const std::vector<int>& to) {
  into.resize(n);
  if (from.stored())
    for (std::size_t i = 0; i < to.size(); ++i)
      if (to[i] >= 0) into.set(static_cast<std::size_t>(to[i]), from[i]);
  from.clear();
  from.shrink_to_fit();
}

// The same for a per-corner array, the corners following their triangle's
// slot (corner k of triangle t goes to corner k of triangle slot[t]).
template <class T, class F>
void scatter_corners_and_free(std::vector<T>& into, std::size_t n, std::vector<T>& from, const std::vector<int>& slot, F&& f) {
  into.resize(n);
  for (std::size_t t = 0; t < slot.size(); ++t)
    if (slot[t] >= 0)
      for (std::size_t k = 0; k < 3; ++k) into[3 * static_cast<std::size_t>(slot[t]) + k] = f(from[3 * t + k]);
  std::vector<T>().swap(from);
}

void scatter_corners_and_free(RefArray& into, std::size_t n, RefArray& from, const std::vector<int>& slot) {
  into.resize(n);
  if (from.stored())
    for (std::size_t t = 0; t < slot.size(); ++t)
      if (slot[t] >= 0)
        for (std::size_t k = 0; k < 3; ++k) into.set(3 * static_cast<std::size_t>(slot[t]) + k, from[3 * t + k]);
  from.clear();
  from.shrink_to_fit();
}

// The slot of each live element of a part (the free slots of `free` first,
// then new ones from `next` on); -1 for the others.
std::vector<int> assign_slots(const std::vector<char>& live, std::vector<int>& free, std::size_t& next) {
  std::vector<int> slot(live.size(), -1);
  for (std::size_t i = 0; i < live.size(); ++i) {
    if (!live[i]) continue;
    if (!free.empty()) {
      slot[i] = free.back();
      free.pop_back();
    } else {
      slot[i] = static_cast<int>(next++);
    }
  }
  return slot;
}

}  // namespace

bool SurfaceMesh::links_restorable() const {
  // Around each vertex a: the edges leaving it (a -> b, opposite prev of
  // the fan's corner) run to distinct vertices, so do the edges reaching it;
  // a border edge leaving a has no edge reaching a from the same vertex.
  std::vector<int> out, in;
  for (Vertex a : vertices()) {
    out.clear();
    in.clear();
    for (Corner k : fan_corners(a)) {
      out.push_back(vertex(next(k)).idx);
      in.push_back(vertex(prev(k)).idx);
    }
    for (std::size_t i = 0; i < out.size(); ++i)
      for (std::size_t j = i + 1; j < out.size(); ++j)
        if (out[i] == out[j] || in[i] == in[j]) return false;
    std::size_t i = 0;
    for (Corner k : fan_corners(a)) {
      if (is_boundary_edge(prev(k)) && std::find(in.begin(), in.end(), out[i]) != in.end()) return false;
      ++i;
    }
  }
  return true;
}

bool SurfaceMesh::release_links() {
  if (links_released() || !links_restorable()) return false;
  std::vector<int>().swap(to_);
  if (free_vertices_.empty()) std::vector<int>().swap(vcorner_);
  return true;
}

void SurfaceMesh::restore_links() {
  if (links_released()) rebuild_links();
  if (vcorner_.size() != vpos_.size()) rebuild_vertex_corners();
}

void SurfaceMesh::rebuild_vertex_corners() {
  vcorner_.assign(vpos_.size(), -1);
  for (std::size_t c = 0; c < tv_.size(); ++c)
    if (tv_[3 * (c / 3)] >= 0) vcorner_[static_cast<std::size_t>(tv_[c])] = static_cast<int>(c);
  for (std::size_t v = 0; v < vpos_.size(); ++v) update_vertex_corner(Vertex(static_cast<int>(v)));
}

void SurfaceMesh::rebuild_links() {
  const std::size_t nc = tv_.size(), nv = vpos_.size();
  auto from = [&](std::size_t c) { return tv_[3 * (c / 3) + (c % 3 + 1) % 3]; };
  auto to = [&](std::size_t c) { return tv_[3 * (c / 3) + (c % 3 + 2) % 3]; };
  // The corners by the first vertex of their edge, in increasing order:
  // start[v] counts up to the end of v's run, then back down to its start
  // as the corners are placed from the last one.
  std::vector<int> start(nv + 1, 0);
  for (std::size_t c = 0; c < nc; ++c)
    if (tv_[3 * (c / 3)] >= 0) ++start[static_cast<std::size_t>(from(c))];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<int> corners(static_cast<std::size_t>(start[nv]));
  for (std::size_t c = nc; c-- > 0;)
    if (tv_[3 * (c / 3)] >= 0) corners[static_cast<std::size_t>(--start[static_cast<std::size_t>(from(c))])] = static_cast<int>(c);
  to_.assign(nc, -1);
  for (std::size_t c = 0; c < nc; ++c) {
    if (tv_[3 * (c / 3)] < 0 || to_[c] >= 0) continue;
    const int a = from(c), b = to(c);
    for (int i = start[static_cast<std::size_t>(b)]; i < start[static_cast<std::size_t>(b) + 1]; ++i) {
      const auto d = static_cast<std::size_t>(corners[static_cast<std::size_t>(i)]);
      if (to(d) != a) continue;
      to_[c] = static_cast<int>(d);
      to_[d] = static_cast<int>(c);
      break;
    }
  }
}

AbsorbMap SurfaceMesh::absorb(SurfaceMesh&& part, const std::vector<int>& existing) {
  const std::size_t pv = part.vpos_.size(), pt = part.tv_.size() / 3;
  AbsorbMap map;
  // Slots: the new vertices and the triangles; existing vertices keep theirs.
  // 1: a new vertex; 2: one of this mesh already (existing); 0: deleted.
  std::vector<char> kind(pv, 0);
  for (std::size_t v = 0; v < pv; ++v)
    if (part.vcorner_[v] != kDeletedMark) kind[v] = v < existing.size() && existing[v] >= 0 ? 2 : 1;
  std::vector<char> live(pv, 0);
  for (std::size_t v = 0; v < pv; ++v) live[v] = kind[v] == 1;
  std::size_t nv = vpos_.size();
  std::vector<int> new_vertex = assign_slots(live, free_vertices_, nv);
  live.assign(pt, 0);
  for (std::size_t t = 0; t < pt; ++t) live[t] = part.tv_[3 * t] >= 0;
  std::size_t nt = tv_.size() / 3;
  map.triangle = assign_slots(live, free_triangles_, nt);
  std::vector<char>().swap(live);
  const auto corner_of = [&](int c) {
    if (c < 0) return -1;
    const int t = map.triangle[static_cast<std::size_t>(c / 3)];
    return t < 0 ? -1 : 3 * t + c % 3;
  };
  const auto same = [](auto x) { return x; };

  // Vertices, one array at a time.
  scatter_and_free(vpos_, nv, part.vpos_, new_vertex, same);
  scatter_and_free(vcorner_, nv, part.vcorner_, new_vertex, corner_of);
  scatter_and_free(vtag_, nv, part.vtag_, new_vertex, same);
  scatter_and_free(vref_, nv, part.vref_, new_vertex);
  vprops_.absorb(part.vprops_, new_vertex, nv);
  // The part's vertices that are this mesh's already keep their slot.
  map.vertex = std::move(new_vertex);
  for (std::size_t v = 0; v < pv; ++v)
    if (kind[v] == 2) map.vertex[v] = existing[v];
  // Triangles and their corners.
  scatter_corners_and_free(tv_, 3 * nt, part.tv_, map.triangle, [&](int v) { return map.vertex[static_cast<std::size_t>(v)]; });
  scatter_corners_and_free(to_, 3 * nt, part.to_, map.triangle, corner_of);
  scatter_corners_and_free(etag_, 3 * nt, part.etag_, map.triangle, same);
  scatter_corners_and_free(eref_, 3 * nt, part.eref_, map.triangle);
  scatter_and_free(ttag_, nt, part.ttag_, map.triangle, same);
  scatter_and_free(tref_, nt, part.tref_, map.triangle);
  tprops_.absorb(part.tprops_, map.triangle, nt);
  part = SurfaceMesh();
  return map;
}

SurfaceMesh SurfaceMesh::empty_like() const {
  SurfaceMesh m;
  m.dimension_ = dimension_;
  m.fields_ = fields_;
  m.vprops_ = vprops_.empty_like();
  m.tprops_ = tprops_.empty_like();
  return m;
}

std::vector<Vec3> SurfaceMesh::release_positions() {
  std::vector<Vec3> out = std::move(vpos_);
  *this = SurfaceMesh();
  return out;
}

void SurfaceMesh::shrink_to_fit() {
  vpos_.shrink_to_fit();
  vcorner_.shrink_to_fit();
  vtag_.shrink_to_fit();
  vref_.shrink_to_fit();
  tv_.shrink_to_fit();
  to_.shrink_to_fit();
  etag_.shrink_to_fit();
  eref_.shrink_to_fit();
  ttag_.shrink_to_fit();
  tref_.shrink_to_fit();
  free_vertices_.shrink_to_fit();
  free_triangles_.shrink_to_fit();
  vprops_.shrink_to_fit();
  tprops_.shrink_to_fit();
}

void SurfaceMesh::clear() {
  vpos_.clear();
  vcorner_.clear();
  vtag_.clear();
  vref_.clear();
  tv_.clear();
  to_.clear();
  etag_.clear();
  eref_.clear();
  ttag_.clear();
  tref_.clear();
  free_vertices_.clear();
  free_triangles_.clear();
  vprops_.resize(0);
  tprops_.resize(0);
}

void SurfaceMesh::reserve(int nv, int nt) {
  const auto v = static_cast<std::size_t>(nv), c = 3 * static_cast<std::size_t>(nt);
  reserve_huge(vpos_, v);
  reserve_huge(vcorner_, v);
  reserve_huge(vtag_, v);
  vref_.reserve(nv);
  reserve_huge(tv_, c);
  reserve_huge(to_, c);
  reserve_huge(etag_, c);
  eref_.reserve(3 * static_cast<std::size_t>(nt));
  ttag_.reserve(nt);
  tref_.reserve(nt);
  vprops_.reserve(nv);
  tprops_.reserve(nt);
}

// --- fields -----------------------------------------------------------------------

Property<FieldValue> SurfaceMesh::add_field(const std::string& name, FieldKind kind, int ncomp) {
  auto p = vprops_.add<FieldValue>("field:" + name, FieldValue{});
  fields_.push_back(FieldInfo{name, kind, ncomp});
  return p;
}

void SurfaceMesh::remove_field(const std::string& name) {
  vprops_.remove("field:" + name);
  std::erase_if(fields_, [&](const FieldInfo& f) { return f.name == name; });
}

Property<FieldValue> SurfaceMesh::get_field(const std::string& name) const {
  return vprops_.get<FieldValue>("field:" + name);
}

// --- validation -----------------------------------------------------------------

ValidationReport SurfaceMesh::validate() const {
  ValidationReport r;
  auto err = [&](const std::string& s) {
    if (r.errors.size() < 1000) r.errors.push_back(s);
  };
  const int nv = vertex_capacity(), nt = triangle_capacity();
  if (vcorner_.size() != vpos_.size() || vtag_.size() != vpos_.size() || vref_.size() != vpos_.size())
    err("vertex arrays have different sizes");
  if (to_.size() != tv_.size() || etag_.size() != tv_.size() || eref_.size() != tv_.size() ||
      ttag_.size() * 3 != tv_.size() || tref_.size() * 3 != tv_.size())
    err("triangle arrays have different sizes");
  if (!r.ok()) return r;
  if (vprops_.size() != vpos_.size() || !vprops_.sizes_consistent()) err("vertex property arrays not sized");
  if (tprops_.size() != static_cast<std::size_t>(nt) || !tprops_.sizes_consistent())
    err("triangle property arrays not sized");

  // free lists
  std::vector<char> vfree(nv, 0), tfree(nt, 0);
  for (int v : free_vertices_) {
    if (v < 0 || v >= nv) { err("free vertex " + std::to_string(v) + " out of range"); continue; }
    if (vfree[v]++) err("vertex " + std::to_string(v) + " twice in the free list");
    if (vcorner_[v] != kDeletedMark) err("free vertex " + std::to_string(v) + " not marked deleted");
  }
  for (int t : free_triangles_) {
    if (t < 0 || t >= nt) { err("free triangle " + std::to_string(t) + " out of range"); continue; }
    if (tfree[t]++) err("triangle " + std::to_string(t) + " twice in the free list");
    if (tv_[3 * t] >= 0) err("free triangle " + std::to_string(t) + " not marked deleted");
  }
  for (int v = 0; v < nv; ++v)
    if (vcorner_[v] == kDeletedMark && !vfree[v]) err("deleted vertex " + std::to_string(v) + " not in the free list");
  for (int t = 0; t < nt; ++t)
    if (tv_[3 * t] < 0 && !tfree[t]) err("deleted triangle " + std::to_string(t) + " not in the free list");

  // triangles and opposite links
  std::vector<int> corners_at(nv, 0);
  for (int t = 0; t < nt; ++t) {
    if (tv_[3 * t] < 0) {
      if (tv_[3 * t + 1] >= 0 || tv_[3 * t + 2] >= 0) err("deleted triangle " + std::to_string(t) + " has vertices");
      continue;
    }
    const auto ts = [t] { return "triangle " + std::to_string(t); };
    bool ids_ok = true;
    for (int k = 0; k < 3; ++k) {
      int v = tv_[3 * t + k];
      if (v < 0 || v >= nv || vcorner_[v] == kDeletedMark) {
        err(ts() + ": vertex id " + std::to_string(v) + " invalid or deleted");
        ids_ok = false;
      }
    }
    if (!ids_ok) continue;
    for (int k = 0; k < 3; ++k) ++corners_at[tv_[3 * t + k]];
    if (tv_[3 * t] == tv_[3 * t + 1] || tv_[3 * t + 1] == tv_[3 * t + 2] || tv_[3 * t] == tv_[3 * t + 2])
      err(ts() + ": degenerate (repeated vertex)");
    for (int k = 0; k < 3; ++k) {
      int c = 3 * t + k, o = to_[c];
      if (o < 0) continue;
      if (o >= static_cast<int>(tv_.size()) || tv_[3 * (o / 3)] < 0) {
        err(ts() + ": opposite corner " + std::to_string(o) + " invalid or deleted");
        continue;
      }
      if (o / 3 == t) err(ts() + ": linked to itself");
      if (to_[o] != c) err(ts() + ": opposite link of corner " + std::to_string(c) + " not symmetric");
      Corner cc(c), oc(o);
      if (vertex(next(cc)) != vertex(prev(oc)) || vertex(prev(cc)) != vertex(next(oc)))
        err(ts() + ": edge of corner " + std::to_string(c) + " does not match its opposite (orientation)");
      if (etag_[c] != etag_[o] || eref_[c] != eref_[o])
        err(ts() + ": edge data of corner " + std::to_string(c) + " differs from its opposite");
    }
  }

  // vertex fans: the stored corner belongs to v, the fan from it is complete
  // (every corner of v is reached), and a boundary fan starts at the boundary.
  for (int v = 0; v < nv; ++v) {
    int c = vcorner_[v];
    if (c == kDeletedMark) continue;
    const auto vs = [v] { return "vertex " + std::to_string(v); };
    if (c < 0) {
      if (corners_at[v] != 0) err(vs() + ": marked isolated but used by triangles");
      continue;
    }
    if (c >= static_cast<int>(tv_.size()) || tv_[c] != v) {
      err(vs() + ": incident corner " + std::to_string(c) + " does not belong to it");
      continue;
    }
    int count = 0;
    bool closed = false;
    Corner start(c), cur = start;
    while (true) {
      ++count;
      if (tv_[cur.idx] != v) {
        err(vs() + ": fan walk reached a corner of another vertex");
        break;
      }
      Corner n = swing_ccw(cur);
      if (!n.is_valid()) break;
      if (n == start) { closed = true; break; }
      if (count > corners_at[v]) break;
      cur = n;
    }
    if (count != corners_at[v])
      err(vs() + ": non-manifold or broken fan (" + std::to_string(count) + " of " + std::to_string(corners_at[v]) +
          " corners reached)");
    if (!closed && to_[prev(start).idx] >= 0)
      err(vs() + ": open fan does not start at its boundary edge");
  }
  return r;
}

}  // namespace anisurf
