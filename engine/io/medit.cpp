// Medit mesh files: ASCII .mesh and binary .meshb (the GMF format of libMeshb).
//
// Both readers fill a MeshData through one Collector that converts the file's
// 1-based ids to 0-based ones and checks each id against the section it refers
// to (immediately when that section was read already, at the end otherwise),
// so that every refusal names the file, the line (or byte) and the entity.
// Volume elements are skipped with a warning; quadrilaterals are split.
#include <algorithm>
#include <array>
#include <charconv>
#include <climits>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/huge_pages.h"
#include "io/formats.h"
#include "io/parallel_lines.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

// --- section table ----------------------------------------------------------

enum class Role {
  Version,
  Dimension,
  End,
  Vertices,
  Edges,
  Triangles,
  Quadrilaterals,
  Corners,
  Ridges,
  RequiredVertices,
  RequiredEdges,
  RequiredTriangles,
  Normals,
  NormalAtVertices,
  Tangents,
  TangentAtVertices,
  Skipped,  // known layout but not used here (volume elements ...): skipped with a warning
};

struct SectionInfo {
  const char* name;    // keyword of the ASCII format
  int code;            // GMF keyword code of the binary format
  Role role;
  int dim_reals;       // reals per entity, in multiples of the dimension
  int ints;            // integers per entity (ids and reference)
  const char* entity;  // singular, for messages
};

// Keyword codes and layouts from libMeshb's keyword table.
constexpr int kGmfDimension = 3;
constexpr int kGmfEnd = 54;
constexpr SectionInfo kSections[] = {
    {"MeshVersionFormatted", 1, Role::Version, 0, 0, "version"},
    {"Dimension", kGmfDimension, Role::Dimension, 0, 0, "dimension"},
    {"Vertices", 4, Role::Vertices, 1, 1, "vertex"},
    {"Edges", 5, Role::Edges, 0, 3, "edge"},
    {"Triangles", 6, Role::Triangles, 0, 4, "triangle"},
    {"Quadrilaterals", 7, Role::Quadrilaterals, 0, 5, "quadrilateral"},
    {"Tetrahedra", 8, Role::Skipped, 0, 5, "tetrahedron"},
    {"Prisms", 9, Role::Skipped, 0, 7, "prism"},
    {"Pentahedra", 9, Role::Skipped, 0, 7, "prism"},
    {"Hexahedra", 10, Role::Skipped, 0, 9, "hexahedron"},
    {"Corners", 13, Role::Corners, 0, 1, "corner"},
    {"Ridges", 14, Role::Ridges, 0, 1, "ridge"},
    {"RequiredVertices", 15, Role::RequiredVertices, 0, 1, "required vertex"},
    {"RequiredEdges", 16, Role::RequiredEdges, 0, 1, "required edge"},
    {"RequiredTriangles", 17, Role::RequiredTriangles, 0, 1, "required triangle"},
    {"RequiredQuadrilaterals", 18, Role::Skipped, 0, 1, "required quadrilateral"},
    {"TangentAtEdgeVertices", 19, Role::Skipped, 0, 3, "tangent at edge vertex"},
    {"NormalAtVertices", 20, Role::NormalAtVertices, 0, 2, "normal at vertex"},
    {"NormalAtTriangleVertices", 21, Role::Skipped, 0, 3, "normal at triangle vertex"},
    {"NormalAtQuadrilateralVertices", 22, Role::Skipped, 0, 4, "normal at quadrilateral vertex"},
    {"Pyramids", 49, Role::Skipped, 0, 6, "pyramid"},
    {"End", kGmfEnd, Role::End, 0, 0, "end"},
    {"Tangents", 59, Role::Tangents, 1, 0, "tangent"},
    {"Normals", 60, Role::Normals, 1, 0, "normal"},
    {"TangentAtVertices", 61, Role::TangentAtVertices, 0, 2, "tangent at vertex"},
};

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

// Section of an ASCII keyword (case-insensitive), or nullptr.
const SectionInfo* section_by_name(std::string_view token) {
  if (token.empty() || !std::isalpha(static_cast<unsigned char>(token[0]))) return nullptr;
  for (const auto& s : kSections)
    if (iequals(token, s.name)) return &s;
  return nullptr;
}

const SectionInfo* section_by_code(long long code) {
  for (const auto& s : kSections)
    if (s.code == code) return &s;
  return nullptr;
}

// --- number parsing -----------------------------------------------------------

// --- collector shared by both readers -------------------------------------------

enum class Target { Vertex, Edge, Triangle, Normal, Tangent, Count_ };
constexpr const char* kTargetName[] = {"vertex", "edge", "triangle", "normal", "tangent"};
constexpr const char* kTargetSection[] = {"Vertices", "Edges", "Triangles", "Normals", "Tangents"};

class Collector {
 public:
  Collector(std::string path, bool binary) : path_(std::move(path)), binary_(binary) {
    counts_.fill(-1);
  }

  MeshData data;

  // "path:line: " or "path: byte N: ".
  std::string where(long long loc) const {
    return binary_ ? path_ + ": byte " + std::to_string(loc) + ": " : path_ + ":" + std::to_string(loc) + ": ";
  }
  [[noreturn]] void fail(long long loc, const std::string& message) const { throw IoError(where(loc) + message); }
  void warn(long long loc, const std::string& message) { data.warnings.push_back(where(loc) + message); }

  // Refuses a section that appears twice (ids would be ambiguous).
  void seen(const SectionInfo& s, long long loc) {
    const auto i = static_cast<std::size_t>(&s - kSections);
    if (seen_[i] >= 0)
      fail(loc, std::string("second ") + s.name + " section (the first one is at " + (binary_ ? "byte " : "line ") +
                    std::to_string(seen_[i]) + "), expected each section once");
    seen_[i] = loc;
  }

  // The number of entries of a target section, fixed once it has been read.
  void set_count(Target t, std::size_t n) { counts_[static_cast<int>(t)] = static_cast<long long>(n); }
  // That number, or -1 before the section has been read.
  long long count(Target t) const { return counts_[static_cast<int>(t)]; }

  // Converts a 1-based id of `target` read at `loc` for entity `index`
  // (0-based) of section `s`; checks its range now or at finish().
  int id(long long value, Target target, const SectionInfo& s, long long index, long long loc) {
    const long long n = counts_[static_cast<int>(target)];
    // Mmg numbers the tangents of TangentAtVertices after the normals: such
    // ids are checked (and renumbered) at finish().
    const bool maybe_after_normals = target == Target::Tangent;
    if (value < 1 || value > INT_MAX || (n >= 0 && value > n && !maybe_after_normals))
      fail(loc, id_message(value, target, s, index, n));
    if (n < 0 || value > n) pending_.push_back({loc, value, index, &s, target});
    return static_cast<int>(value - 1);
  }

  void add_quad(const std::array<int, 4>& q, int ref) {
    quads_.push_back(q);
    quad_refs_.push_back(ref);
  }

  // Checks the ids whose target section came later, splits quadrilaterals.
  void finish() {
    set_count(Target::Vertex, data.vertices.size());
    set_count(Target::Edge, data.edges.size());
    set_count(Target::Triangle, data.triangles.size());
    set_count(Target::Normal, data.normals.size());
    set_count(Target::Tangent, data.tangents.size());
    const auto n_normals = static_cast<long long>(data.normals.size());
    std::size_t renumbered = 0;
    for (const auto& p : pending_) {
      const long long n = counts_[static_cast<int>(p.target)];
      if (p.value <= n) continue;
      if (p.target == Target::Tangent && n_normals > 0 && p.value > n_normals && p.value - n_normals <= n) {
        data.tangent_at_vertex[static_cast<std::size_t>(p.index)][1] = static_cast<int>(p.value - n_normals - 1);
        ++renumbered;
        continue;
      }
      fail(p.loc, id_message(p.value, p.target, *p.section, p.index, n));
    }
    if (renumbered > 0)
      data.warnings.push_back(path_ + ": " + std::to_string(renumbered) +
                              " TangentAtVertices ids numbered after the normals (Mmg layout) renumbered");
    if (!quads_.empty()) {
      // Appended after the file's triangles so that RequiredTriangles ids stay valid.
      for (std::size_t q = 0; q < quads_.size(); ++q) {
        const auto& v = quads_[q];
        data.triangles.push_back({v[0], v[1], v[2]});
        data.triangles.push_back({v[0], v[2], v[3]});
        data.triangle_refs.push_back(quad_refs_[q]);
        data.triangle_refs.push_back(quad_refs_[q]);
      }
      data.warnings.push_back(path_ + ": " + std::to_string(quads_.size()) + " quadrilaterals split into " +
                              std::to_string(2 * quads_.size()) + " triangles");
    }
  }

 private:
  struct Pending {
    long long loc;
    long long value;
    long long index;
    const SectionInfo* section;
    Target target;
  };

  static std::string id_message(long long value, Target target, const SectionInfo& s, long long index, long long n) {
    std::string m = std::string(s.entity) + " " + std::to_string(index + 1) + ": " + kTargetName[static_cast<int>(target)] +
                    " id " + std::to_string(value) + " out of range";
    if (n > 0)
      m += " 1.." + std::to_string(n);
    else if (n == 0)
      m += std::string(": the file has no ") + kTargetSection[static_cast<int>(target)] + ", expected none";
    else
      m += ", expected an id >= 1";
    if (value == 0) m += " (ids are 1-based)";
    return m;
  }

  std::string path_;
  bool binary_;
  std::array<long long, static_cast<int>(Target::Count_)> counts_{};
  std::array<long long, std::size(kSections)> seen_ = [] {
    std::array<long long, std::size(kSections)> a{};
    a.fill(-1);
    return a;
  }();
  std::vector<Pending> pending_;
  std::vector<std::array<int, 4>> quads_;
  std::vector<int> quad_refs_;
};

// Target of the k-th id of an entity of a section.
Target id_target(Role role, int k) {
  switch (role) {
    case Role::Ridges:
    case Role::RequiredEdges:
      return Target::Edge;
    case Role::RequiredTriangles:
      return Target::Triangle;
    case Role::NormalAtVertices:
      return k == 0 ? Target::Vertex : Target::Normal;
    case Role::TangentAtVertices:
      return k == 0 ? Target::Vertex : Target::Tangent;
    default:
      return Target::Vertex;
  }
}

const char* id_field(Target t) {
  switch (t) {
    case Target::Edge: return "edge id";
    case Target::Triangle: return "triangle id";
    case Target::Normal: return "normal id";
    case Target::Tangent: return "tangent id";
    default: return "vertex id";
  }
}

constexpr const char* kCoordName[] = {"x coordinate", "y coordinate", "z coordinate"};
constexpr const char* kCompName[] = {"x component", "y component", "z component"};

// Stores one parsed entity of a section into the collector's data. `ids` are
// 0-based already; `reals` has `dim` values.
void store_entity(Collector& c, Role role, int dim, const double* reals, const int* ids, int ref) {
  MeshData& d = c.data;
  switch (role) {
    case Role::Vertices:
      d.vertices.push_back({reals[0], reals[1], dim == 3 ? reals[2] : 0.0});
      d.vertex_refs.push_back(ref);
      break;
    case Role::Edges:
      d.edges.push_back({ids[0], ids[1]});
      d.edge_refs.push_back(ref);
      break;
    case Role::Triangles:
      d.triangles.push_back({ids[0], ids[1], ids[2]});
      d.triangle_refs.push_back(ref);
      break;
    case Role::Quadrilaterals:
      c.add_quad({ids[0], ids[1], ids[2], ids[3]}, ref);
      break;
    case Role::Corners: d.corners.push_back(ids[0]); break;
    case Role::Ridges: d.ridges.push_back(ids[0]); break;
    case Role::RequiredVertices: d.required_vertices.push_back(ids[0]); break;
    case Role::RequiredEdges: d.required_edges.push_back(ids[0]); break;
    case Role::RequiredTriangles: d.required_triangles.push_back(ids[0]); break;
    case Role::Normals: d.normals.push_back({reals[0], reals[1], dim == 3 ? reals[2] : 0.0}); break;
    case Role::Tangents: d.tangents.push_back({reals[0], reals[1], dim == 3 ? reals[2] : 0.0}); break;
    case Role::NormalAtVertices: d.normal_at_vertex.push_back({ids[0], ids[1]}); break;
    case Role::TangentAtVertices: d.tangent_at_vertex.push_back({ids[0], ids[1]}); break;
    default: break;
  }
}

// Sets the target count once a section that others refer to is complete.
void section_done(Collector& c, Role role) {
  switch (role) {
    case Role::Vertices: c.set_count(Target::Vertex, c.data.vertices.size()); break;
    case Role::Edges: c.set_count(Target::Edge, c.data.edges.size()); break;
    case Role::Triangles: c.set_count(Target::Triangle, c.data.triangles.size()); break;
    case Role::Normals: c.set_count(Target::Normal, c.data.normals.size()); break;
    case Role::Tangents: c.set_count(Target::Tangent, c.data.tangents.size()); break;
    default: break;
  }
}

// Number of ids (without the reference) per entity of a used section.
int id_count(const SectionInfo& s) {
  switch (s.role) {
    case Role::Vertices:
    case Role::Normals:
    case Role::Tangents:
      return 0;
    case Role::Edges:
    case Role::Triangles:
    case Role::Quadrilaterals:
      return s.ints - 1;
    default:
      return s.ints;
  }
}
bool has_ref(const SectionInfo& s) {
  return s.role == Role::Vertices || s.role == Role::Edges || s.role == Role::Triangles ||
         s.role == Role::Quadrilaterals;
}

// --- ASCII reader ------------------------------------------------------------------

class AsciiReader {
 public:
  AsciiReader(std::string contents, const std::string& path)
      : size_(contents.size()), in_(std::move(contents), path, '#'), c_(path, false) {}

  MeshData run() {
    std::string_view t;
    if (!in_.next(t)) in_.fail("empty file, expected 'MeshVersionFormatted'");
    const SectionInfo* s = section_by_name(t);
    if (!s || s->role != Role::Version)
      in_.fail("expected 'MeshVersionFormatted' at the start of a Medit file, found " + quoted(t));
    bool ended = false;
    bool got = true;
    while (got) {
      if (!s) {
        double x;
        if (parse_real(t, x))
          in_.fail("expected a section keyword, found the number " + quoted(t) +
                   " (more entries than the count of the section before?)");
        c_.warn(in_.line(), "unknown section " + quoted(t) + " skipped");
        while ((got = in_.next(t)) && !(s = section_by_name(t))) {
        }
        continue;
      }
      if (s->role == Role::End) {
        ended = true;
        break;
      }
      read_section(*s);
      got = in_.next(t);
      s = got ? section_by_name(t) : nullptr;
    }
    if (!ended) c_.warn(in_.line(), "no 'End' keyword at the end of the file");
    c_.finish();
    return std::move(c_.data);
  }

 private:
  // What is being read, for messages.
  struct Ctx {
    const SectionInfo* s;
    long long index;  // 0-based entity
    long long count;  // announced
    const char* field;
  };

  // At the end of the file, errors name the line of the last token.
  [[noreturn]] void fail_eof(int last_line, const std::string& message) const {
    throw IoError(in_.path() + ":" + std::to_string(last_line) + ": " + message);
  }

  [[noreturn]] void fail_token(const Ctx& x, bool eof, std::string_view t, int last_line = 0) const {
    std::string m = std::string(x.s->entity) + " " + std::to_string(x.index + 1) + ": expected " + x.field;
    const std::string announced = std::string(" (") + x.s->name + " announced " + std::to_string(x.count) + ", only " +
                                  std::to_string(x.index) + " complete";
    if (eof)
      fail_eof(last_line, m + ", found the end of the file" + announced + ": truncated file?)");
    else if (section_by_name(t))
      m += ", found the keyword " + quoted(t) + announced + ")";
    else
      m += " (a number), found " + quoted(t);
    in_.fail(m);
  }

  double real(const Ctx& x) {
    std::string_view t;
    const int last = in_.line();
    if (!in_.next(t)) fail_token(x, true, t, last);
    double v;
    if (!parse_real(t, v)) fail_token(x, false, t);
    if (!std::isfinite(v))
      in_.fail(std::string(x.s->entity) + " " + std::to_string(x.index + 1) + ": " + x.field + " is not finite (" +
               quoted(t) + "), expected a finite number");
    return v;
  }

  long long integer(const Ctx& x) {
    std::string_view t;
    const int last = in_.line();
    if (!in_.next(t)) fail_token(x, true, t, last);
    long long v;
    if (!parse_integer(t, v)) fail_token(x, false, t);
    return v;
  }

  // The integer after MeshVersionFormatted or Dimension.
  long long header_int(const SectionInfo& s, const char* what) {
    std::string_view t;
    const int last = in_.line();
    if (!in_.next(t)) fail_eof(last, std::string(s.name) + ": expected " + what + ", found the end of the file");
    long long v;
    if (!parse_integer(t, v)) in_.fail(std::string(s.name) + ": expected " + what + ", found " + quoted(t));
    return v;
  }

  // Reads the count of a section: an integer in 0..INT_MAX.
  long long count(const SectionInfo& s) {
    std::string_view t;
    const int last = in_.line();
    if (!in_.next(t)) fail_eof(last, std::string(s.name) + ": expected the number of entries, found the end of the file");
    long long n;
    if (!parse_integer(t, n))
      in_.fail(std::string(s.name) + ": expected the number of entries (an integer), found " + quoted(t));
    if (n < 0) in_.fail(std::string(s.name) + ": negative count " + std::to_string(n) + ", expected a count >= 0");
    if (n > INT_MAX)
      in_.fail(std::string(s.name) + ": count " + std::to_string(n) + " too large, expected at most " +
               std::to_string(INT_MAX));
    return n;
  }

  void read_section(const SectionInfo& s) {
    const int keyword_line = in_.line();
    c_.seen(s, keyword_line);
    Ctx x{&s, 0, 1, ""};
    switch (s.role) {
      case Role::Version: {
        const long long v = header_int(s, "a version 1, 2, 3 or 4");
        if (v < 1 || v > 4) in_.fail("MeshVersionFormatted " + std::to_string(v) + " unsupported, expected 1, 2, 3 or 4");
        c_.data.version = v == 1 ? 1 : 2;
        return;
      }
      case Role::Dimension: {
        const long long v = header_int(s, "the dimension 2 or 3");
        if (v != 2 && v != 3) in_.fail("Dimension " + std::to_string(v) + " unsupported, expected 2 or 3");
        dim_ = static_cast<int>(v);
        c_.data.dimension = dim_;
        return;
      }
      default:
        break;
    }
    if (s.dim_reals > 0 && dim_ == 0)
      in_.fail(std::string(s.name) + " section before 'Dimension', expected 'Dimension 2' or 'Dimension 3' first");
    const long long n = count(s);
    x.count = n;
    const int tokens = s.dim_reals * std::max(dim_, 2) + s.ints;
    if (s.role == Role::Skipped) {
      skip(x, n * tokens);
      if (n > 0)
        c_.warn(keyword_line, std::to_string(n) + " " + s.name + " skipped (not used by a surface mesh)");
      return;
    }
    reserve(s, std::min<long long>(n, static_cast<long long>(size_ / (2 * static_cast<std::size_t>(tokens)) + 1)));
    if (read_lines_in_parallel(s, n, tokens)) {
      section_done(c_, s.role);
      return;
    }
    const int nids = id_count(s);
    const bool ref = has_ref(s);
    const int nreals = s.dim_reals * dim_;
    const char* const* real_names = s.role == Role::Vertices ? kCoordName : kCompName;
    double reals[3] = {0, 0, 0};
    int ids[4] = {0, 0, 0, 0};
    for (long long i = 0; i < n; ++i) {
      x.index = i;
      for (int k = 0; k < nreals; ++k) {
        x.field = real_names[k];
        reals[k] = real(x);
      }
      for (int k = 0; k < nids; ++k) {
        const Target target = id_target(s.role, k);
        x.field = id_field(target);
        const long long v = integer(x);
        ids[k] = c_.id(v, target, s, i, in_.line());
      }
      int r = 0;
      if (ref) {
        x.field = "reference";
        const long long v = integer(x);
        if (v < INT_MIN || v > INT_MAX)
          in_.fail(std::string(s.entity) + " " + std::to_string(i + 1) + ": reference " + std::to_string(v) +
                   " out of range, expected a 32-bit integer");
        r = static_cast<int>(v);
      }
      store_entity(c_, s.role, dim_, reals, ids, r);
    }
    section_done(c_, s.role);
  }

  // A large Vertices or Triangles section written one entity per line (as
  // the writers do) parsed on parallel chunks straight into the data: the
  // values the token by token reading takes. False, with nothing read,
  // where that reading must follow (parse_lines_in_parallel), a value it
  // would refuse with its message, or a vertex id out of range or read
  // before the Vertices.
  bool read_lines_in_parallel(const SectionInfo& s, long long n, int tokens) {
    constexpr long long kMinLines = 65536;
    const bool vertices = s.role == Role::Vertices;
    const long long nv = c_.count(Target::Vertex);
    // A token takes 2 bytes of text at least: a count the file cannot hold
    // allocates nothing here.
    if (!(vertices || s.role == Role::Triangles) || n < kMinLines || (!vertices && nv < 0) ||
        static_cast<std::size_t>(n) * static_cast<std::size_t>(tokens) > size_ / 2)
      return false;
    MeshData& d = c_.data;
    const auto count = static_cast<std::size_t>(n);
    if (vertices) {
      d.vertices.resize(count);
      d.vertex_refs.resize(count);
    } else {
      d.triangles.resize(count);
      d.triangle_refs.resize(count);
    }
    const int dim = dim_;
    const bool taken = parse_lines_in_parallel(in_, n, tokens, kMinLines, [&](long long line, const std::string_view* token) {
      const auto i = static_cast<std::size_t>(line);
      long long ref = 0;
      if (!parse_integer(token[tokens - 1], ref) || ref < INT_MIN || ref > INT_MAX) return false;
      if (vertices) {
        double r[3] = {0, 0, 0};
        for (int j = 0; j < dim; ++j)
          if (!parse_real(token[j], r[j]) || !std::isfinite(r[j])) return false;
        d.vertices[i] = {r[0], r[1], r[2]};
        d.vertex_refs[i] = static_cast<int>(ref);
      } else {
        long long id[3];
        for (int j = 0; j < 3; ++j)
          if (!parse_integer(token[j], id[j]) || id[j] < 1 || id[j] > nv) return false;
        d.triangles[i] = {static_cast<int>(id[0] - 1), static_cast<int>(id[1] - 1), static_cast<int>(id[2] - 1)};
        d.triangle_refs[i] = static_cast<int>(ref);
      }
      return true;
    });
    if (!taken && vertices) {
      d.vertices.clear();
      d.vertex_refs.clear();
    } else if (!taken) {
      d.triangles.clear();
      d.triangle_refs.clear();
    }
    return taken;
  }

  // Skips `n` number tokens of a skipped section; a keyword among them means
  // the section is shorter than announced.
  void skip(Ctx& x, long long n) {
    const long long per = std::max<long long>(1, x.s->dim_reals * std::max(dim_, 2) + x.s->ints);
    std::string_view t;
    x.field = "a number";
    for (long long k = 0; k < n; ++k) {
      x.index = k / per;
      const int last = in_.line();
      if (!in_.next(t)) fail_token(x, true, t, last);
      if (std::isalpha(static_cast<unsigned char>(t[0])) && section_by_name(t)) fail_token(x, false, t);
    }
  }

  void reserve(const SectionInfo& s, long long n) {
    MeshData& d = c_.data;
    const auto m = static_cast<std::size_t>(n);
    switch (s.role) {
      case Role::Vertices: reserve_huge(d.vertices, m); reserve_huge(d.vertex_refs, m); break;
      case Role::Triangles: reserve_huge(d.triangles, m); reserve_huge(d.triangle_refs, m); break;
      case Role::Edges: reserve_huge(d.edges, m); reserve_huge(d.edge_refs, m); break;
      default: break;
    }
  }

  std::size_t size_;
  TextReader in_;
  Collector c_;
  int dim_ = 0;
};

// --- binary reader -------------------------------------------------------------------

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& path) : in_(ByteReader::from_file(path)), c_(path, true) {}

  MeshData run() {
    read_header();
    c_.data.dimension = dim_;
    c_.data.version = version_ == 1 ? 1 : 2;
    bool ended = false;
    while (!in_.at_end()) {
      const std::size_t at = in_.offset();
      const long long code = i32("a keyword code");
      const std::size_t next_at = in_.offset();
      const long long next = position();
      const SectionInfo* s = section_by_code(code);
      if (s && s->role == Role::End) {
        ended = true;
        break;
      }
      const std::string name = s ? std::string(s->name) : "keyword " + std::to_string(code);
      if (next != 0 && next <= static_cast<long long>(at))
        fail_at(next_at, name + " (at byte " + std::to_string(at) + "): next-keyword position " + std::to_string(next) +
                             " points backwards, expected a position after byte " + std::to_string(at));
      if (!s || s->role == Role::Version || s->role == Role::Dimension) {
        check_next(next, next_at, name);
        if (s) c_.seen(*s, at);
        c_.warn(at, "unknown " + name + " skipped");
        if (next == 0) {
          c_.warn(at, name + " has no next-keyword position: the rest of the file is ignored");
          break;
        }
        in_.seek(static_cast<std::size_t>(next));
        continue;
      }
      c_.seen(*s, at);
      read_section(*s, next, next_at);
      if (next == 0) break;
      in_.seek(static_cast<std::size_t>(next));
    }
    if (!ended) c_.warn(static_cast<long long>(in_.offset()), "no End keyword");
    c_.finish();
    return std::move(c_.data);
  }

 private:
  [[noreturn]] void fail_at(std::size_t at, const std::string& message) {
    in_.seek(at);
    in_.fail(message);
  }

  long long i32(const char* what) { return in_.read<std::int32_t>(what, swap_); }
  long long integer(const char* what) {
    return version_ >= 4 ? in_.read<std::int64_t>(what, swap_) : in_.read<std::int32_t>(what, swap_);
  }
  double real(const char* what) {
    return version_ == 1 ? static_cast<double>(in_.read<float>(what, swap_)) : in_.read<double>(what, swap_);
  }
  long long position() {
    return version_ >= 3 ? in_.read<std::int64_t>("a next-keyword position", swap_)
                         : in_.read<std::int32_t>("a next-keyword position", swap_);
  }
  std::size_t int_size() const { return version_ >= 4 ? 8 : 4; }
  std::size_t real_size() const { return version_ == 1 ? 4 : 8; }

  void read_header() {
    const long long code = i32("the endianness code 1");
    if (code == 1)
      swap_ = false;
    else if (code == 0x01000000)
      swap_ = true;
    else
      fail_at(0, "not a Medit binary file: expected the code 1 (or 16777216 byte-swapped), found " +
                     std::to_string(code));
    const long long v = i32("the version");
    if (v < 1 || v > 4) fail_at(4, ".meshb version " + std::to_string(v) + " unsupported, expected 1, 2, 3 or 4");
    version_ = static_cast<int>(v);
    const long long kw = i32("the Dimension keyword");
    if (kw != kGmfDimension)
      fail_at(8, "expected the Dimension keyword (code 3) after the header, found keyword code " + std::to_string(kw));
    position();
    const std::size_t at = in_.offset();
    const long long d = i32("the dimension");
    if (d != 2 && d != 3) fail_at(at, "Dimension " + std::to_string(d) + " unsupported, expected 2 or 3");
    dim_ = static_cast<int>(d);
    c_.seen(*section_by_code(kGmfDimension), 8);
  }

  void check_next(long long next, std::size_t next_at, const std::string& name) {
    if (next < 0 || next > static_cast<long long>(in_.size()))
      fail_at(next_at, name + ": next-keyword position " + std::to_string(next) + " is past the end of the file, expected at most " +
                           std::to_string(in_.size()) + " (truncated or corrupt file)");
  }

  void read_section(const SectionInfo& s, long long next, std::size_t next_at) {
    const std::size_t count_at = in_.offset();
    const long long n = integer("the number of entries");
    if (n < 0) fail_at(count_at, std::string(s.name) + ": negative count " + std::to_string(n) + ", expected a count >= 0");
    if (n > INT_MAX)
      fail_at(count_at, std::string(s.name) + ": count " + std::to_string(n) + " too large, expected at most " +
                            std::to_string(INT_MAX));
    const std::size_t entity_bytes =
        static_cast<std::size_t>(s.dim_reals * dim_) * real_size() + static_cast<std::size_t>(s.ints) * int_size();
    const std::size_t start = in_.offset();
    const long long bytes = n * static_cast<long long>(entity_bytes);
    if (bytes > static_cast<long long>(in_.size() - start))
      fail_at(start, std::string("truncated file: ") + s.name + " announces " + std::to_string(n) + " entries (" +
                         std::to_string(bytes) + " bytes from byte " + std::to_string(start) + ") but the file has " +
                         std::to_string(in_.size()) + " bytes, expected at least " + std::to_string(start + bytes));
    check_next(next, next_at, s.name);
    if (next != 0 && static_cast<long long>(start) + bytes > next)
      fail_at(next_at, std::string(s.name) + ": next-keyword position " + std::to_string(next) +
                           " lies inside its data, expected at least " + std::to_string(start + bytes));
    if (s.role == Role::Skipped) {
      if (n > 0) c_.warn(static_cast<long long>(count_at), std::to_string(n) + " " + s.name + " skipped (not used by a surface mesh)");
      in_.seek(start + static_cast<std::size_t>(bytes));
      return;
    }
    const int nids = id_count(s);
    const bool ref = has_ref(s);
    const int nreals = s.dim_reals * dim_;
    double reals[3] = {0, 0, 0};
    int ids[4] = {0, 0, 0, 0};
    for (long long i = 0; i < n; ++i) {
      for (int k = 0; k < nreals; ++k) {
        const std::size_t at = in_.offset();
        reals[k] = real("a real");
        if (!std::isfinite(reals[k]))
          fail_at(at, std::string(s.entity) + " " + std::to_string(i + 1) + ": " +
                          (s.role == Role::Vertices ? kCoordName[k] : kCompName[k]) + " is not finite, expected a finite number");
      }
      for (int k = 0; k < nids; ++k) {
        const auto at = static_cast<long long>(in_.offset());
        ids[k] = c_.id(integer("an id"), id_target(s.role, k), s, i, at);
      }
      int r = 0;
      if (ref) {
        const std::size_t at = in_.offset();
        const long long v = integer("a reference");
        if (v < INT_MIN || v > INT_MAX)
          fail_at(at, std::string(s.entity) + " " + std::to_string(i + 1) + ": reference " + std::to_string(v) +
                          " out of range, expected a 32-bit integer");
        r = static_cast<int>(v);
      }
      store_entity(c_, s.role, dim_, reals, ids, r);
    }
    section_done(c_, s.role);
  }

  ByteReader in_;
  Collector c_;
  bool swap_ = false;
  int version_ = 2;
  int dim_ = 3;
};

// --- writers -----------------------------------------------------------------------------

// Refuses data a reader would refuse (or that cannot be written).
void check_writable(const std::string& path, const MeshData& d) {
  auto refuse = [&](const std::string& m) { throw IoError(path + ": cannot write: " + m); };
  if (d.dimension != 2 && d.dimension != 3)
    refuse("dimension " + std::to_string(d.dimension) + ", expected 2 or 3");
  auto sized = [&](std::size_t refs, std::size_t n, const char* what) {
    if (refs != 0 && refs != n)
      refuse(std::string(what) + " has " + std::to_string(refs) + " entries, expected 0 or " + std::to_string(n));
  };
  sized(d.vertex_refs.size(), d.vertices.size(), "vertex_refs");
  sized(d.triangle_refs.size(), d.triangles.size(), "triangle_refs");
  sized(d.edge_refs.size(), d.edges.size(), "edge_refs");
  if (d.vertices.size() > static_cast<std::size_t>(INT_MAX)) refuse("too many vertices");
  auto in_range = [&](long long id, std::size_t n, const char* what, std::size_t index) {
    if (id < 0 || id >= static_cast<long long>(n))
      refuse(std::string(what) + " " + std::to_string(index) + ": id " + std::to_string(id) + " out of range 0.." +
             std::to_string(static_cast<long long>(n) - 1));
  };
  const std::size_t nv = d.vertices.size();
  for (std::size_t i = 0; i < nv; ++i)
    if (!is_finite(d.vertices[i])) refuse("vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (std::size_t i = 0; i < d.triangles.size(); ++i)
    for (int v : d.triangles[i]) in_range(v, nv, "triangle", i);
  for (std::size_t i = 0; i < d.edges.size(); ++i)
    for (int v : d.edges[i]) in_range(v, nv, "edge", i);
  for (std::size_t i = 0; i < d.corners.size(); ++i) in_range(d.corners[i], nv, "corner", i);
  for (std::size_t i = 0; i < d.required_vertices.size(); ++i) in_range(d.required_vertices[i], nv, "required vertex", i);
  for (std::size_t i = 0; i < d.ridges.size(); ++i) in_range(d.ridges[i], d.edges.size(), "ridge", i);
  for (std::size_t i = 0; i < d.required_edges.size(); ++i) in_range(d.required_edges[i], d.edges.size(), "required edge", i);
  for (std::size_t i = 0; i < d.required_triangles.size(); ++i)
    in_range(d.required_triangles[i], d.triangles.size(), "required triangle", i);
  for (std::size_t i = 0; i < d.normals.size(); ++i)
    if (!is_finite(d.normals[i])) refuse("normal " + std::to_string(i) + " is not finite");
  for (std::size_t i = 0; i < d.tangents.size(); ++i)
    if (!is_finite(d.tangents[i])) refuse("tangent " + std::to_string(i) + " is not finite");
  for (std::size_t i = 0; i < d.normal_at_vertex.size(); ++i) {
    in_range(d.normal_at_vertex[i][0], nv, "normal at vertex", i);
    in_range(d.normal_at_vertex[i][1], d.normals.size(), "normal at vertex", i);
  }
  for (std::size_t i = 0; i < d.tangent_at_vertex.size(); ++i) {
    in_range(d.tangent_at_vertex[i][0], nv, "tangent at vertex", i);
    in_range(d.tangent_at_vertex[i][1], d.tangents.size(), "tangent at vertex", i);
  }
}

int ref_or_zero(const std::vector<int>& refs, std::size_t i) { return refs.empty() ? 0 : refs[i]; }

// ASCII text in a buffer flushed to the file in large blocks.
class TextOut {
 public:
  TextOut(AtomicFile& f, int version) : f_(f), version_(version) { buf_.reserve(1 << 20); }
  TextOut& s(std::string_view t) {
    buf_.append(t);
    return *this;
  }
  TextOut& i(long long v) {
    char b[24];
    auto r = std::to_chars(b, b + sizeof b, v);
    buf_.append(b, r.ptr);
    return *this;
  }
  TextOut& r(double v) {
    if (version_ == 1) {
      char b[32];
      auto res = std::to_chars(b, b + sizeof b, static_cast<float>(v));
      buf_.append(b, res.ptr);
    } else {
      append_double(buf_, v);
    }
    return *this;
  }
  TextOut& nl() {
    buf_.push_back('\n');
    if (buf_.size() > (1 << 20)) flush();
    return *this;
  }
  void flush() {
    f_.stream().write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }

 private:
  AtomicFile& f_;
  int version_;
  std::string buf_;
};

// Binary GMF data in memory, with the next-keyword positions patched.
class GmfOut {
 public:
  explicit GmfOut(int version) : version_(version) {}
  void i32(std::int32_t v) { put(v); }
  void integer(long long v) {
    if (version_ >= 4)
      put(static_cast<std::int64_t>(v));
    else
      put(static_cast<std::int32_t>(v));
  }
  void real(double v) {
    if (version_ == 1)
      put(static_cast<float>(v));
    else
      put(v);
  }
  // Starts a keyword (count < 0: no count field); returns the slot of its
  // next-keyword position.
  std::size_t begin(int code, long long count) {
    i32(code);
    const std::size_t slot = buf_.size();
    if (version_ >= 3)
      put(std::int64_t{0});
    else
      put(std::int32_t{0});
    if (count >= 0) {
      if (version_ >= 4)
        put(static_cast<std::int64_t>(count));
      else
        put(static_cast<std::int32_t>(count));
    }
    return slot;
  }
  void end(std::size_t slot) {
    if (version_ >= 3) {
      const auto p = static_cast<std::int64_t>(buf_.size());
      std::memcpy(&buf_[slot], &p, sizeof p);
    } else {
      const auto p = static_cast<std::int32_t>(buf_.size());
      std::memcpy(&buf_[slot], &p, sizeof p);
    }
  }
  const std::string& bytes() const { return buf_; }

 private:
  template <class T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    buf_.append(b, sizeof(T));
  }
  int version_;
  std::string buf_;
};

// Upper bound of the size of a .meshb version 2 file (to switch to 64-bit
// positions when 32-bit ones could overflow).
std::size_t meshb_size_bound(const MeshData& d) {
  const std::size_t per_keyword = 4 + 8 + 8;
  std::size_t n = 64 + 20 * per_keyword;
  n += d.vertices.size() * (3 * 8 + 8) + d.triangles.size() * 4 * 8 + d.edges.size() * 3 * 8;
  n += (d.corners.size() + d.ridges.size() + d.required_vertices.size() + d.required_edges.size() +
        d.required_triangles.size()) * 8;
  n += (d.normals.size() + d.tangents.size()) * 24 + (d.normal_at_vertex.size() + d.tangent_at_vertex.size()) * 16;
  return n;
}

void write_meshb(const std::string& path, const MeshData& d, int version) {
  check_writable(path, d);
  const int dim = d.dimension;
  GmfOut out(version);
  out.i32(1);
  out.i32(version);
  std::size_t slot = out.begin(kGmfDimension, -1);
  out.i32(dim);
  out.end(slot);
  auto point = [&](const Vec3& p) {
    for (int k = 0; k < dim; ++k) out.real(p[k]);
  };
  auto ids = [&](int code, const std::vector<int>& v) {
    if (v.empty()) return;
    const std::size_t s = out.begin(code, static_cast<long long>(v.size()));
    for (int x : v) out.integer(x + 1);
    out.end(s);
  };
  auto pairs = [&](int code, const std::vector<std::array<int, 2>>& v) {
    if (v.empty()) return;
    const std::size_t s = out.begin(code, static_cast<long long>(v.size()));
    for (const auto& p : v) {
      out.integer(p[0] + 1);
      out.integer(p[1] + 1);
    }
    out.end(s);
  };
  auto points = [&](int code, const std::vector<Vec3>& v) {
    if (v.empty()) return;
    const std::size_t s = out.begin(code, static_cast<long long>(v.size()));
    for (const auto& p : v) point(p);
    out.end(s);
  };
  if (!d.vertices.empty()) {
    slot = out.begin(section_by_name("Vertices")->code, static_cast<long long>(d.vertices.size()));
    for (std::size_t i = 0; i < d.vertices.size(); ++i) {
      point(d.vertices[i]);
      out.integer(ref_or_zero(d.vertex_refs, i));
    }
    out.end(slot);
  }
  if (!d.edges.empty()) {
    slot = out.begin(section_by_name("Edges")->code, static_cast<long long>(d.edges.size()));
    for (std::size_t i = 0; i < d.edges.size(); ++i) {
      out.integer(d.edges[i][0] + 1);
      out.integer(d.edges[i][1] + 1);
      out.integer(ref_or_zero(d.edge_refs, i));
    }
    out.end(slot);
  }
  if (!d.triangles.empty()) {
    slot = out.begin(section_by_name("Triangles")->code, static_cast<long long>(d.triangles.size()));
    for (std::size_t i = 0; i < d.triangles.size(); ++i) {
      for (int v : d.triangles[i]) out.integer(v + 1);
      out.integer(ref_or_zero(d.triangle_refs, i));
    }
    out.end(slot);
  }
  ids(section_by_name("Corners")->code, d.corners);
  ids(section_by_name("Ridges")->code, d.ridges);
  ids(section_by_name("RequiredVertices")->code, d.required_vertices);
  ids(section_by_name("RequiredEdges")->code, d.required_edges);
  ids(section_by_name("RequiredTriangles")->code, d.required_triangles);
  points(section_by_name("Normals")->code, d.normals);
  pairs(section_by_name("NormalAtVertices")->code, d.normal_at_vertex);
  points(section_by_name("Tangents")->code, d.tangents);
  pairs(section_by_name("TangentAtVertices")->code, d.tangent_at_vertex);
  out.begin(kGmfEnd, -1);  // the last keyword keeps next position 0

  AtomicFile f(path);
  f.stream().write(out.bytes().data(), static_cast<std::streamsize>(out.bytes().size()));
  f.commit();
}

}  // namespace

MeshData read_medit(const std::string& path) {
  AsciiReader reader(read_file_contents(path), path);
  return reader.run();
}

MeshData read_medit_binary(const std::string& path) {
  BinaryReader reader(path);
  return reader.run();
}

void write_medit(const std::string& path, const MeshData& d, int version) {
  if (version != 1 && version != 2)
    throw IoError(path + ": cannot write Medit version " + std::to_string(version) + ", expected 1 or 2");
  check_writable(path, d);
  const int dim = d.dimension;
  AtomicFile f(path);
  TextOut out(f, version);
  out.s("MeshVersionFormatted ").i(version).nl().nl();
  out.s("Dimension ").i(dim).nl().nl();
  auto point = [&](const Vec3& p) {
    for (int k = 0; k < dim; ++k) {
      if (k) out.s(" ");
      out.r(p[k]);
    }
  };
  auto header = [&](const char* name, std::size_t n) { out.s(name).nl().i(static_cast<long long>(n)).nl(); };
  if (!d.vertices.empty()) {
    header("Vertices", d.vertices.size());
    for (std::size_t i = 0; i < d.vertices.size(); ++i) {
      point(d.vertices[i]);
      out.s(" ").i(ref_or_zero(d.vertex_refs, i)).nl();
    }
    out.nl();
  }
  if (!d.edges.empty()) {
    header("Edges", d.edges.size());
    for (std::size_t i = 0; i < d.edges.size(); ++i)
      out.i(d.edges[i][0] + 1).s(" ").i(d.edges[i][1] + 1).s(" ").i(ref_or_zero(d.edge_refs, i)).nl();
    out.nl();
  }
  if (!d.triangles.empty()) {
    header("Triangles", d.triangles.size());
    for (std::size_t i = 0; i < d.triangles.size(); ++i) {
      const auto& t = d.triangles[i];
      out.i(t[0] + 1).s(" ").i(t[1] + 1).s(" ").i(t[2] + 1).s(" ").i(ref_or_zero(d.triangle_refs, i)).nl();
    }
    out.nl();
  }
  auto ids = [&](const char* name, const std::vector<int>& v) {
    if (v.empty()) return;
    header(name, v.size());
    for (int x : v) out.i(x + 1).nl();
    out.nl();
  };
  auto points = [&](const char* name, const std::vector<Vec3>& v) {
    if (v.empty()) return;
    header(name, v.size());
    for (const auto& p : v) {
      point(p);
      out.nl();
    }
    out.nl();
  };
  auto pairs = [&](const char* name, const std::vector<std::array<int, 2>>& v) {
    if (v.empty()) return;
    header(name, v.size());
    for (const auto& p : v) out.i(p[0] + 1).s(" ").i(p[1] + 1).nl();
    out.nl();
  };
  ids("Corners", d.corners);
  ids("Ridges", d.ridges);
  ids("RequiredVertices", d.required_vertices);
  ids("RequiredEdges", d.required_edges);
  ids("RequiredTriangles", d.required_triangles);
  points("Normals", d.normals);
  pairs("NormalAtVertices", d.normal_at_vertex);
  points("Tangents", d.tangents);
  pairs("TangentAtVertices", d.tangent_at_vertex);
  out.s("End").nl();
  out.flush();
  f.commit();
}

void write_medit_binary(const std::string& path, const MeshData& data) {
  // Version 2 (double reals, 32-bit ints and positions) unless the file could
  // exceed 2 GiB: then version 3 (64-bit positions).
  const int version = meshb_size_bound(data) < static_cast<std::size_t>(INT_MAX) ? 2 : 3;
  write_meshb(path, data, version);
}

}  // namespace anisurf::io
