// Legacy VTK files.
// Writer (ASCII, DATASET POLYDATA) for ParaView: points, Medit edges as LINES
// and triangles as POLYGONS; CELL_DATA "ref" (edge then triangle references,
// in the VTK cell order lines before polygons); POINT_DATA "vertex_ref" and
// one array per field: SCALARS, VECTORS (2D vectors padded with 0) or TENSORS
// (the symmetric tensor as its full 3x3 matrix).
// Reader: ASCII or BINARY (big-endian), DATASET POLYDATA or
// UNSTRUCTURED_GRID, cells in the classic layout (count then ids) or the 5.x
// one (OFFSETS / CONNECTIVITY). Triangles (POLYGONS of 3 vertices, cell types
// 5 and 7) and lines (LINES, polylines split into segments; cell type 3)
// become triangles and edges; other cells are skipped with a warning.
// CELL_DATA: the first integer scalar named "ref", "medit:ref",
// "gmsh:physical" or "CellEntityIds" gives the refs. POINT_DATA: an integer
// scalar "vertex_ref" or "medit:ref" gives the vertex refs; SCALARS (1..6
// components) become scalar fields, VECTORS and NORMALS vector fields,
// TENSORS (3x3, made symmetric with a warning if they are not) and TENSORS6
// (XX YY ZZ XY YZ XZ) tensor fields, FIELD arrays by their component count
// (1 scalar, 3 vector, 6 and 9 tensor as above). Lookup tables, colors,
// texture coordinates and METADATA are skipped.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/field_layout.h"
#include "io/formats.h"
#include "io/mixed_reader.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

// VTK array names are single tokens: blanks become '_'; names stay unique.
std::string array_name(const std::string& name, std::size_t k, std::set<std::string>& used) {
  std::string s = name.empty() ? "field" + std::to_string(k) : name;
  for (char& c : s)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  std::string unique = s;
  for (int i = 1; used.count(unique); ++i) unique = s + "_" + std::to_string(i);
  used.insert(unique);
  return unique;
}

// The checks of every writer (field_layout.h), and the legacy format's own
// limits on field components.
void check(const std::string& path, const MeshData& d) {
  check_for_writing(path, d, false);
  auto refuse = [&](const std::string& m) { throw IoError(path + ": cannot write: " + m); };
  for (const auto& f : d.fields) {
    if (f.info.kind == FieldKind::Tensor && f.info.ncomp != 3 && f.info.ncomp != 6)
      refuse("tensor field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected 3 or 6");
    if (f.info.kind != FieldKind::Tensor && f.info.ncomp > 4 && !(f.info.kind == FieldKind::Vector && f.info.ncomp <= 3))
      refuse("field '" + f.info.name + "' has " + std::to_string(f.info.ncomp) + " components, expected at most 4");
  }
}

}  // namespace

void write_vtk(const std::string& path, const MeshData& d) {
  check(path, d);
  const std::size_t nv = d.vertices.size(), nt = d.triangles.size(), ne = d.edges.size();
  std::string b;
  b.reserve(64 * (nv + nt + ne) + 256);
  auto num = [&](double v) { append_double(b, v); };
  b += "# vtk DataFile Version 3.0\nanisurf surface mesh\nASCII\nDATASET POLYDATA\n";
  b += "POINTS " + std::to_string(nv) + " double\n";
  for (const auto& p : d.vertices) {
    num(p.x);
    b += ' ';
    num(p.y);
    b += ' ';
    num(p.z);
    b += '\n';
  }
  if (ne > 0) {
    b += "LINES " + std::to_string(ne) + " " + std::to_string(3 * ne) + "\n";
    for (const auto& e : d.edges) b += "2 " + std::to_string(e[0]) + " " + std::to_string(e[1]) + "\n";
  }
  if (nt > 0) {
    b += "POLYGONS " + std::to_string(nt) + " " + std::to_string(4 * nt) + "\n";
    for (const auto& t : d.triangles)
      b += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  }
  if (ne + nt > 0) {
    b += "CELL_DATA " + std::to_string(ne + nt) + "\nSCALARS ref int 1\nLOOKUP_TABLE default\n";
    for (std::size_t i = 0; i < ne; ++i) b += std::to_string(d.edge_refs.empty() ? 0 : d.edge_refs[i]) + "\n";
    for (std::size_t i = 0; i < nt; ++i) b += std::to_string(d.triangle_refs.empty() ? 0 : d.triangle_refs[i]) + "\n";
  }
  if (nv > 0 && (!d.vertex_refs.empty() || !d.fields.empty())) {
    b += "POINT_DATA " + std::to_string(nv) + "\n";
    std::set<std::string> used{"vertex_ref"};
    if (!d.vertex_refs.empty()) {
      b += "SCALARS vertex_ref int 1\nLOOKUP_TABLE default\n";
      for (int r : d.vertex_refs) b += std::to_string(r) + "\n";
    }
    for (std::size_t k = 0; k < d.fields.size(); ++k) {
      const FieldData& f = d.fields[k];
      const std::string name = array_name(f.info.name, k, used);
      const int nc = f.info.ncomp;
      const bool tensor = f.info.kind == FieldKind::Tensor;
      const bool vector = f.info.kind == FieldKind::Vector && nc <= 3;
      if (tensor)
        b += "TENSORS " + name + " double\n";
      else if (vector)
        b += "VECTORS " + name + " double\n";
      else
        b += "SCALARS " + name + " double " + std::to_string(nc) + "\nLOOKUP_TABLE default\n";
      for (std::size_t i = 0; i < nv; ++i) {
        const double* v = f.values.data() + i * static_cast<std::size_t>(nc);
        if (tensor) {
          const auto m = full_tensor(v, nc);
          for (int r = 0; r < 3; ++r) {
            num(m[3 * r]);
            b += ' ';
            num(m[3 * r + 1]);
            b += ' ';
            num(m[3 * r + 2]);
            b += '\n';
          }
        } else {
          const int n_out = vector ? 3 : nc;
          for (int c = 0; c < n_out; ++c) {
            if (c) b += ' ';
            num(c < nc ? v[c] : 0.0);
          }
          b += '\n';
        }
      }
    }
  }
  AtomicFile file(path);
  file.stream().write(b.data(), static_cast<std::streamsize>(b.size()));
  file.commit();
}

}  // namespace anisurf::io

namespace anisurf::io {
namespace {

enum class LegacyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

bool legacy_type(std::string_view s, LegacyType& t) {
  static const std::pair<const char*, LegacyType> names[] = {
      {"bit", LegacyType::UInt8},          {"char", LegacyType::Int8},          {"unsigned_char", LegacyType::UInt8},
      {"short", LegacyType::Int16},        {"unsigned_short", LegacyType::UInt16}, {"int", LegacyType::Int32},
      {"unsigned_int", LegacyType::UInt32}, {"long", LegacyType::Int64},        {"unsigned_long", LegacyType::UInt64},
      {"vtktypeint64", LegacyType::Int64}, {"vtktypeuint64", LegacyType::UInt64}, {"vtkIdType", LegacyType::Int64},
      {"float", LegacyType::Float32},      {"double", LegacyType::Float64},     {"vtktypeint8", LegacyType::Int8},
      {"vtktypeuint8", LegacyType::UInt8}, {"vtktypeint16", LegacyType::Int16}, {"vtktypeuint16", LegacyType::UInt16},
      {"vtktypeint32", LegacyType::Int32}, {"vtktypeuint32", LegacyType::UInt32},
      {"vtktypefloat32", LegacyType::Float32}, {"vtktypefloat64", LegacyType::Float64}};
  for (const auto& [n, v] : names)
    if (s == n) {
      t = v;
      return s != "bit";
    }
  return false;
}

std::size_t legacy_size(LegacyType t) {
  switch (t) {
    case LegacyType::Int8:
    case LegacyType::UInt8: return 1;
    case LegacyType::Int16:
    case LegacyType::UInt16: return 2;
    case LegacyType::Int32:
    case LegacyType::UInt32:
    case LegacyType::Float32: return 4;
    default: return 8;
  }
}

bool legacy_integer(LegacyType t) { return t != LegacyType::Float32 && t != LegacyType::Float64; }

// One attribute array of POINT_DATA or CELL_DATA.
struct LegacyArray {
  std::string name;
  std::string kind;  // SCALARS VECTORS NORMALS TENSORS TENSORS6 FIELD
  bool integer = false;
  int ncomp = 1;
  std::vector<double> values;
};

// Cells of one section in the file's cell numbering: (kind, items) with kind
// 1 triangle, 2 edges (items segments), 0 skipped.
using CellItems = std::vector<std::pair<int, int>>;

class LegacyVtkReader {
 public:
  explicit LegacyVtkReader(const std::string& path) : r_(read_file_contents(path), path) {}
  MeshData read();

 private:
  std::vector<std::string_view> header_line();
  std::vector<double> values(long long n, std::string_view type, const char* what);
  long long count(std::string_view t, const char* what);
  // Cells of a section: ids of each cell (classic or 5.x layout).
  std::vector<std::vector<int>> cells(long long n, long long size, const char* section);
  void attribute(std::string_view keyword, const std::vector<std::string_view>& args);
  void finish(MeshData& d);

  MixedReader r_;
  bool binary_ = false;
  bool poly_ = true;
  long long n_points_ = -1;
  std::vector<Vec3> points_;
  std::map<std::string, std::vector<std::vector<int>>> sections_;  // POLYDATA sections
  std::vector<std::vector<int>> ug_cells_;
  std::vector<int> ug_types_;
  bool cell_target_ = false;  // current attribute data: CELL_DATA (true) or POINT_DATA
  long long target_count_ = 0;
  std::vector<LegacyArray> point_arrays_, cell_arrays_;
  std::vector<std::string> warnings_;
};

std::vector<std::string_view> LegacyVtkReader::header_line() {
  std::vector<std::string_view> out;
  std::string_view line = r_.rest_of_line();
  std::size_t p = 0;
  while (p < line.size()) {
    while (p < line.size() && (line[p] == ' ' || line[p] == '\t')) ++p;
    const std::size_t s = p;
    while (p < line.size() && line[p] != ' ' && line[p] != '\t') ++p;
    if (p > s) out.push_back(line.substr(s, p - s));
  }
  return out;
}

long long LegacyVtkReader::count(std::string_view t, const char* what) {
  long long v = 0;
  if (!parse_integer(t, v) || v < 0) r_.fail_expected(what, t);
  if (v > (1LL << 40)) r_.fail(std::string(what) + " " + std::to_string(v) + " impossible, expected at most 2^40");
  return v;
}

std::vector<double> LegacyVtkReader::values(long long n, std::string_view type_name, const char* what) {
  LegacyType type;
  if (!legacy_type(type_name, type))
    r_.fail_expected("a data type (float, double, int, unsigned_char ...)", type_name);
  r_.set_binary(binary_);
  r_.check_fits(n, binary_ ? legacy_size(type) : 2, what);
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(n));
  for (long long i = 0; i < n; ++i) {
    double x = 0;
    if (!binary_) {
      x = r_.read_double(what);
    } else {
      const bool swap = host_is_little_endian();
      switch (type) {
        case LegacyType::Int8: x = r_.read<std::int8_t>(what, swap); break;
        case LegacyType::UInt8: x = r_.read<std::uint8_t>(what, swap); break;
        case LegacyType::Int16: x = r_.read<std::int16_t>(what, swap); break;
        case LegacyType::UInt16: x = r_.read<std::uint16_t>(what, swap); break;
        case LegacyType::Int32: x = r_.read<std::int32_t>(what, swap); break;
        case LegacyType::UInt32: x = r_.read<std::uint32_t>(what, swap); break;
        case LegacyType::Int64: x = static_cast<double>(r_.read<std::int64_t>(what, swap)); break;
        case LegacyType::UInt64: x = static_cast<double>(r_.read<std::uint64_t>(what, swap)); break;
        case LegacyType::Float32: x = r_.read<float>(what, swap); break;
        case LegacyType::Float64: x = r_.read<double>(what, swap); break;
      }
    }
    if (!std::isfinite(x)) r_.fail(std::string(what) + " is not a finite number");
    v.push_back(x);
  }
  r_.set_binary(false);
  return v;
}

std::vector<std::vector<int>> LegacyVtkReader::cells(long long n, long long size, const char* section) {
  std::vector<std::vector<int>> out;
  auto point_id = [&](double v) {
    if (!(v >= 0 && v < static_cast<double>(n_points_)))
      r_.fail(std::string(section) + ": point id " + format_double(v) +
              " out of range, expected 0.." + std::to_string(n_points_ - 1));
    return static_cast<int>(v);
  };
  if (r_.peek() == "OFFSETS") {  // 5.x: n offsets (cells + 1), size connectivity entries
    r_.token("'OFFSETS'");
    const auto off_args = header_line();
    if (off_args.size() != 1) r_.fail("expected 'OFFSETS <type>'");
    const std::vector<double> off = values(n, off_args[0], "cell offset");
    r_.skip_space();
    r_.expect("CONNECTIVITY");
    const auto conn_args = header_line();
    if (conn_args.size() != 1) r_.fail("expected 'CONNECTIVITY <type>'");
    const std::vector<double> conn = values(size, conn_args[0], "point id");
    for (long long i = 0; i + 1 < n; ++i) {
      const double a = off[static_cast<std::size_t>(i)], b = off[static_cast<std::size_t>(i + 1)];
      if (!(a >= 0 && a <= b && b <= static_cast<double>(size)))
        r_.fail(std::string(section) + ": offsets " + std::to_string(a) + ".." + std::to_string(b) + " of cell " +
                std::to_string(i) + " out of order, expected 0.." + std::to_string(size));
      std::vector<int> ids;
      for (auto k = static_cast<std::size_t>(a); k < static_cast<std::size_t>(b); ++k) ids.push_back(point_id(conn[k]));
      out.push_back(std::move(ids));
    }
    return out;
  }
  const std::vector<double> flat = values(size, "int", "cell entry");
  std::size_t k = 0;
  for (long long i = 0; i < n; ++i) {
    if (k >= flat.size()) r_.fail(std::string(section) + ": " + std::to_string(i) + " cells in " + std::to_string(size) +
                                  " entries, expected " + std::to_string(n));
    const double m = flat[k++];
    if (!(m >= 0 && m <= static_cast<double>(flat.size() - k)))
      r_.fail(std::string(section) + ": cell " + std::to_string(i) + " of " + std::to_string(m) +
              " points overruns the section's " + std::to_string(size) + " entries");
    std::vector<int> ids;
    for (long long j = 0; j < static_cast<long long>(m); ++j) ids.push_back(point_id(flat[k++]));
    out.push_back(std::move(ids));
  }
  if (k != flat.size())
    r_.fail(std::string(section) + ": " + std::to_string(flat.size() - k) + " entries left after " + std::to_string(n) +
            " cells, expected exactly " + std::to_string(size));
  return out;
}

void LegacyVtkReader::attribute(std::string_view keyword, const std::vector<std::string_view>& args) {
  std::vector<LegacyArray>& target = cell_target_ ? cell_arrays_ : point_arrays_;
  const long long n = target_count_;
  auto type_of = [&](std::size_t i) {
    if (args.size() <= i) r_.fail("expected " + std::string(keyword) + " <name> <type>");
    return args[i];
  };
  LegacyArray a;
  a.kind = std::string(keyword);
  if (keyword == "SCALARS") {
    a.name = std::string(type_of(0));
    const std::string_view type = type_of(1);
    a.ncomp = args.size() > 2 ? static_cast<int>(count(args[2], "component count")) : 1;
    if (a.ncomp < 1 || a.ncomp > 4) r_.fail("SCALARS " + a.name + " has " + std::to_string(a.ncomp) + " components, expected 1..4");
    r_.skip_space();
    if (r_.peek() == "LOOKUP_TABLE") header_line();
    LegacyType t;
    a.integer = legacy_type(type, t) && legacy_integer(t);
    a.values = values(n * a.ncomp, type, "scalar value");
  } else if (keyword == "VECTORS" || keyword == "NORMALS" || keyword == "TENSORS" || keyword == "TENSORS6") {
    a.name = std::string(type_of(0));
    a.ncomp = keyword == "TENSORS" ? 9 : keyword == "TENSORS6" ? 6 : 3;
    a.values = values(n * a.ncomp, type_of(1), "value");
  } else if (keyword == "FIELD") {
    const long long arrays = args.size() > 1 ? count(args[1], "array count") : 0;
    for (long long i = 0; i < arrays; ++i) {
      r_.skip_space();
      const auto f = header_line();
      if (f.size() < 4) r_.fail("expected '<name> <components> <tuples> <type>' of a FIELD array");
      LegacyArray fa;
      fa.kind = "FIELD";
      fa.name = std::string(f[0]);
      const long long nc = count(f[1], "component count"), tuples = count(f[2], "tuple count");
      if (nc < 1 || nc > 64) r_.fail("FIELD array " + fa.name + " has " + std::to_string(nc) + " components, expected 1..64");
      if (tuples > static_cast<long long>(r_.size())) r_.check_fits(tuples, 1, "tuple");
      fa.ncomp = static_cast<int>(nc);
      LegacyType t;
      fa.integer = legacy_type(f[3], t) && legacy_integer(t);
      fa.values = values(nc * tuples, f[3], "FIELD value");
      if (tuples != n) {
        warnings_.push_back(r_.path() + ": skipped FIELD array " + fa.name + " of " + std::to_string(tuples) +
                            " tuples (expected " + std::to_string(n) + ")");
        continue;
      }
      target.push_back(std::move(fa));
    }
    return;
  } else if (keyword == "LOOKUP_TABLE") {
    const long long size = args.size() > 1 ? count(args[1], "table size") : 0;
    values(4 * size, binary_ ? "unsigned_char" : "float", "lookup table value");
    return;
  } else if (keyword == "COLOR_SCALARS") {
    const long long nc = args.size() > 1 ? count(args[1], "component count") : 0;
    values(nc * n, binary_ ? "unsigned_char" : "float", "color value");
    warnings_.push_back(r_.path() + ": skipped COLOR_SCALARS " + std::string(type_of(0)));
    return;
  } else if (keyword == "TEXTURE_COORDINATES") {
    const long long dim = args.size() > 1 ? count(args[1], "dimension") : 0;
    values(dim * n, type_of(2), "texture coordinate");
    warnings_.push_back(r_.path() + ": skipped TEXTURE_COORDINATES " + std::string(type_of(0)));
    return;
  }
  target.push_back(std::move(a));
}

MeshData LegacyVtkReader::read() {
  const std::string_view first = r_.rest_of_line();
  if (first.rfind("# vtk DataFile", 0) != 0) r_.fail_expected("'# vtk DataFile Version x.x' (a legacy VTK file)", first);
  r_.rest_of_line();  // title
  const auto format = header_line();
  if (format.size() != 1 || (format[0] != "ASCII" && format[0] != "BINARY"))
    r_.fail_expected("ASCII or BINARY", format.empty() ? std::string_view() : format[0]);
  binary_ = format[0] == "BINARY";
  r_.skip_space();
  r_.expect("DATASET");
  const auto ds = header_line();
  if (ds.size() != 1 || (ds[0] != "POLYDATA" && ds[0] != "UNSTRUCTURED_GRID"))
    r_.fail_expected("DATASET POLYDATA or UNSTRUCTURED_GRID", ds.empty() ? std::string_view() : ds[0]);
  poly_ = ds[0] == "POLYDATA";
  while (!r_.at_end()) {
    const std::string_view kw = r_.token("a keyword");
    const auto args = header_line();
    if (kw == "POINTS") {
      if (args.size() != 2) r_.fail("expected 'POINTS <n> <type>'");
      n_points_ = count(args[0], "point count");
      const std::vector<double> xyz = values(3 * n_points_, args[1], "point coordinate");
      for (long long i = 0; i < n_points_; ++i) points_.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
    } else if ((poly_ && (kw == "VERTICES" || kw == "LINES" || kw == "POLYGONS" || kw == "TRIANGLE_STRIPS")) ||
               (!poly_ && kw == "CELLS")) {
      if (n_points_ < 0) r_.fail(std::string(kw) + " before POINTS, expected POINTS first");
      if (args.size() != 2) r_.fail("expected '" + std::string(kw) + " <n> <size>'");
      const long long n = count(args[0], "cell count"), size = count(args[1], "cell size");
      r_.skip_space();
      auto c = cells(n, size, std::string(kw).c_str());
      if (poly_) sections_[std::string(kw)] = std::move(c);
      else ug_cells_ = std::move(c);
    } else if (!poly_ && kw == "CELL_TYPES") {
      if (args.size() != 1) r_.fail("expected 'CELL_TYPES <n>'");
      const long long n = count(args[0], "cell count");
      if (n != static_cast<long long>(ug_cells_.size()))
        r_.fail("CELL_TYPES " + std::to_string(n) + ", expected " + std::to_string(ug_cells_.size()) + " (the CELLS count)");
      r_.skip_space();
      for (double t : values(n, "int", "cell type")) {
        int type = -1;
        ug_types_.push_back(int_from_double(t, type) ? type : -1);
      }
    } else if (kw == "POINT_DATA" || kw == "CELL_DATA") {
      if (args.size() != 1) r_.fail("expected '" + std::string(kw) + " <n>'");
      cell_target_ = kw == "CELL_DATA";
      target_count_ = count(args[0], "count");
      const long long expected = cell_target_ ? -1 : n_points_;
      if (expected >= 0 && target_count_ != expected)
        r_.fail("POINT_DATA " + std::to_string(target_count_) + ", expected " + std::to_string(expected) + " (the points)");
    } else if (kw == "SCALARS" || kw == "VECTORS" || kw == "NORMALS" || kw == "TENSORS" || kw == "TENSORS6" ||
               kw == "FIELD" || kw == "LOOKUP_TABLE" || kw == "COLOR_SCALARS" || kw == "TEXTURE_COORDINATES") {
      if (target_count_ == 0 && kw != "LOOKUP_TABLE" && kw != "FIELD")
        r_.fail(std::string(kw) + " outside POINT_DATA / CELL_DATA, expected one of them first");
      r_.skip_space();
      attribute(kw, args);
    } else if (kw == "METADATA") {
      while (!r_.at_end() && !r_.rest_of_line().empty()) {
      }
    } else {
      r_.fail_expected("a legacy VTK keyword (POINTS, POLYGONS, CELLS, POINT_DATA ...)", kw);
    }
  }
  if (n_points_ < 0) r_.fail("no POINTS, expected the point coordinates");
  MeshData d;
  finish(d);
  return d;
}

bool is_cell_ref_name(const std::string& n) {
  return n == "ref" || n == "medit:ref" || n == "gmsh:physical" || n == "CellEntityIds";
}

void LegacyVtkReader::finish(MeshData& d) {
  const std::string& path = r_.path();
  d.vertices = points_;
  CellItems items;
  std::map<std::string, long long> skipped;
  auto add_cell = [&](const std::vector<int>& ids, int vtk_type) {
    if ((vtk_type == 5 || vtk_type == 7) && ids.size() == 3) {
      d.triangles.push_back({ids[0], ids[1], ids[2]});
      items.push_back({1, 1});
    } else if ((vtk_type == 3 || vtk_type == 4) && ids.size() >= 2) {
      for (std::size_t k = 0; k + 1 < ids.size(); ++k) d.edges.push_back({ids[k], ids[k + 1]});
      items.push_back({2, static_cast<int>(ids.size() - 1)});
    } else {
      items.push_back({0, 0});
      ++skipped["cells of VTK type " + std::to_string(vtk_type) + " with " + std::to_string(ids.size()) + " points"];
    }
  };
  if (poly_) {
    const std::pair<const char*, int> order[] = {{"VERTICES", 1}, {"LINES", 4}, {"POLYGONS", 7}, {"TRIANGLE_STRIPS", 6}};
    for (const auto& [section, type] : order)
      for (const auto& ids : sections_[section]) add_cell(ids, type);
  } else {
    if (ug_types_.size() != ug_cells_.size()) throw IoError(path + ": CELLS without CELL_TYPES, expected both");
    for (std::size_t i = 0; i < ug_cells_.size(); ++i) add_cell(ug_cells_[i], ug_types_[i]);
  }
  for (const auto& [what, n] : skipped)
    d.warnings.push_back(path + ": skipped " + std::to_string(n) + " " + what + ", expected triangles and lines");
  for (const LegacyArray& a : cell_arrays_) {
    if (!is_cell_ref_name(a.name) || !a.integer || a.ncomp != 1 || !d.triangle_refs.empty() || !d.edge_refs.empty()) {
      d.warnings.push_back(path + ": skipped cell array " + a.name);
      continue;
    }
    if (a.values.size() != items.size())
      throw IoError(path + ": CELL_DATA " + a.name + " has " + std::to_string(a.values.size()) + " values, expected " +
                    std::to_string(items.size()) + " (the cells)");
    d.triangle_refs.assign(d.triangles.size(), 0);
    d.edge_refs.assign(d.edges.size(), 0);
    std::size_t t = 0, e = 0;
    for (std::size_t i = 0; i < items.size(); ++i) {
      int ref = 0;
      if (!int_from_double(a.values[i], ref))
        throw IoError(path + ": CELL_DATA " + a.name + ": reference " + format_double(a.values[i]) +
                      ", expected an integer of the int range");
      if (items[i].first == 1) d.triangle_refs[t++] = ref;
      if (items[i].first == 2)
        for (int k = 0; k < items[i].second; ++k) d.edge_refs[e++] = ref;
    }
  }
  for (const LegacyArray& a : point_arrays_) {
    if (a.values.size() != d.vertices.size() * static_cast<std::size_t>(a.ncomp))
      throw IoError(path + ": POINT_DATA " + a.name + " has " + std::to_string(a.values.size()) + " values, expected " +
                    std::to_string(d.vertices.size()) + " x " + std::to_string(a.ncomp) + " (the points)");
    if ((a.name == "vertex_ref" || a.name == "medit:ref") && a.integer && a.ncomp == 1 && d.vertex_refs.empty()) {
      for (double v : a.values) {
        int ref = 0;
        if (!int_from_double(v, ref))
          throw IoError(path + ": POINT_DATA " + a.name + ": reference " + format_double(v) +
                        ", expected an integer of the int range");
        d.vertex_refs.push_back(ref);
      }
      continue;
    }
    FieldData f;
    long long asymmetric = 0;
    if (a.ncomp == 6) {
      f.info = {a.name, FieldKind::Tensor, 6};
      for (std::size_t i = 0; i < a.values.size(); i += 6) {
        const double* v = a.values.data() + i;  // XX YY ZZ XY YZ XZ
        f.values.insert(f.values.end(), {v[0], v[3], v[1], v[5], v[4], v[2]});
      }
    } else if (a.kind == "SCALARS" || a.ncomp == 2 || a.ncomp == 4 || a.ncomp == 5) {
      f.info = {a.name, FieldKind::Scalar, a.ncomp};
      f.values = a.values;
    } else if (!field_from_layout(a.name, a.ncomp, a.values, f, &asymmetric)) {
      d.warnings.push_back(path + ": skipped point array " + a.name + " of " + std::to_string(a.ncomp) + " components");
      continue;
    }
    if (asymmetric > 0) d.warnings.push_back(asymmetric_warning(path, a.name, asymmetric));
    if (std::any_of(d.fields.begin(), d.fields.end(), [&](const FieldData& g) { return g.info.name == a.name; })) {
      d.warnings.push_back(path + ": skipped a second point array " + a.name);
      continue;
    }
    d.fields.push_back(std::move(f));
  }
  for (std::string& w : warnings_) d.warnings.push_back(std::move(w));
}

}  // namespace

MeshData read_vtk(const std::string& path) {
  LegacyVtkReader reader(path);
  return reader.read();
}

}  // namespace anisurf::io
