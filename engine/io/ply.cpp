// Stanford PLY: ascii, binary_little_endian and binary_big_endian.
// Reading: element `vertex` (x y z of any scalar type, optional `ref`),
// element `face` (list `vertex_indices` or `vertex_index`, optional `ref`;
// polygons fan-triangulated); every other element and property is skipped.
// Writing: vertex x y z as double (+ int ref), face list uchar int
// vertex_indices (+ int ref).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/formats.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_type(std::string_view s, PlyType& t) {
  if (s == "char" || s == "int8") t = PlyType::Int8;
  else if (s == "uchar" || s == "uint8") t = PlyType::UInt8;
  else if (s == "short" || s == "int16") t = PlyType::Int16;
  else if (s == "ushort" || s == "uint16") t = PlyType::UInt16;
  else if (s == "int" || s == "int32") t = PlyType::Int32;
  else if (s == "uint" || s == "uint32") t = PlyType::UInt32;
  else if (s == "float" || s == "float32") t = PlyType::Float32;
  else if (s == "double" || s == "float64") t = PlyType::Float64;
  else return false;
  return true;
}

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 1;
}

bool is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> props;
  int line = 0;
  // Smallest size of one element in a binary file (lists may be empty).
  std::size_t min_binary_size() const {
    std::size_t s = 0;
    for (const auto& p : props) s += p.is_list ? type_size(p.count_type) : type_size(p.type);
    return s;
  }
};

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // first byte after the end_header line
  int body_line = 1;            // line number of the first body line (ascii)
};

// Offset just past the "end_header" line, or npos.
std::size_t find_header_end(const std::string& d) {
  std::size_t p = 0;
  while ((p = d.find("end_header", p)) != std::string::npos) {
    if (p > 0 && d[p - 1] == '\n') {
      std::size_t q = p + 10;
      while (q < d.size() && (d[q] == ' ' || d[q] == '\t' || d[q] == '\r')) ++q;
      if (q < d.size() && d[q] == '\n') return q + 1;
      if (q == d.size()) return q;
    }
    p += 10;
  }
  return std::string::npos;
}

PlyHeader parse_header(const std::string& contents, const std::string& path) {
  PlyHeader h;
  if (contents.compare(0, 3, "ply") != 0 ||
      (contents.size() > 3 && contents[3] != '\n' && contents[3] != '\r' && contents[3] != ' '))
    throw IoError(path + ":1: expected 'ply' on the first line, found '" +
                  contents.substr(0, std::min<std::size_t>(contents.find('\n'), 20)) + "'");
  std::size_t end = find_header_end(contents);
  // Without end_header the parse below fails at the end of the text it gets.
  const std::size_t header_size = end == std::string::npos ? std::min<std::size_t>(contents.size(), 1 << 16) : end;
  h.body_offset = end == std::string::npos ? contents.size() : end;
  TextReader r(contents.substr(0, header_size), path, '\0');
  r.token("'ply'");
  r.rest_of_line();
  bool have_format = false;
  for (;;) {
    std::string_view kw = r.token("'end_header'");
    if (kw == "end_header") break;
    if (kw == "comment" || kw == "obj_info") {
      r.rest_of_line();
      continue;
    }
    std::string_view t;
    if (kw == "format") {
      if (!r.next_on_line(t)) r.fail("expected format name after 'format'");
      if (t == "ascii") h.format = PlyFormat::Ascii;
      else if (t == "binary_little_endian") h.format = PlyFormat::BinaryLittle;
      else if (t == "binary_big_endian") h.format = PlyFormat::BinaryBig;
      else r.fail_expected("format ascii, binary_little_endian or binary_big_endian", t);
      if (!r.next_on_line(t) || t != "1.0") r.fail_expected("format version 1.0", t);
      have_format = true;
    } else if (kw == "element") {
      PlyElement e;
      e.line = r.line();
      if (!r.next_on_line(t)) r.fail("expected element name after 'element'");
      e.name = std::string(t);
      if (!r.next_on_line(t)) r.fail("expected element count after 'element " + e.name + "'");
      e.count = r.parse_int(t, "element count");
      if (e.count < 0) r.fail("element " + e.name + " has negative count " + std::to_string(e.count));
      h.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (h.elements.empty()) r.fail("'property' before any 'element', expected 'element <name> <count>' first");
      PlyProperty p;
      if (!r.next_on_line(t)) r.fail("expected property type after 'property'");
      if (t == "list") {
        p.is_list = true;
        if (!r.next_on_line(t) || !parse_type(t, p.count_type))
          r.fail_expected("list count type (uchar, ushort, uint, int ...)", t);
        if (!is_integer(p.count_type)) r.fail_expected("integer list count type", t);
        if (!r.next_on_line(t) || !parse_type(t, p.type))
          r.fail_expected("list item type (char, uchar, short, ushort, int, uint, float, double)", t);
      } else if (!parse_type(t, p.type)) {
        r.fail_expected("property type (char, uchar, short, ushort, int, uint, float, double or list)", t);
      }
      if (!r.next_on_line(t)) r.fail("expected property name");
      p.name = std::string(t);
      h.elements.back().props.push_back(std::move(p));
    } else {
      r.fail_expected("'format', 'element', 'property', 'comment' or 'end_header'", kw);
    }
    r.rest_of_line();
  }
  if (!have_format) r.fail("missing 'format' line, expected 'format ascii 1.0' or 'format binary_..._endian 1.0'");
  h.body_line = 1 + static_cast<int>(std::count(contents.begin(), contents.begin() + h.body_offset, '\n'));
  return h;
}

// Where the reader stores each property of the vertex and face elements.
enum class Slot { Skip, X, Y, Z, VertexRef, Indices, FaceRef };

struct ElementPlan {
  std::vector<Slot> slots;  // one per property
};

template <class T>
double read_value(ByteReader& b, bool swap, const char* what) {
  return static_cast<double>(b.read<T>(what, swap));
}

double read_binary(ByteReader& b, PlyType t, bool swap, const char* what) {
  switch (t) {
    case PlyType::Int8: return read_value<std::int8_t>(b, swap, what);
    case PlyType::UInt8: return read_value<std::uint8_t>(b, swap, what);
    case PlyType::Int16: return read_value<std::int16_t>(b, swap, what);
    case PlyType::UInt16: return read_value<std::uint16_t>(b, swap, what);
    case PlyType::Int32: return read_value<std::int32_t>(b, swap, what);
    case PlyType::UInt32: return read_value<std::uint32_t>(b, swap, what);
    case PlyType::Float32: return read_value<float>(b, swap, what);
    case PlyType::Float64: return read_value<double>(b, swap, what);
  }
  return 0;
}

}  // namespace

MeshData read_ply(const std::string& path) {
  std::string contents = read_file_contents(path);
  const PlyHeader h = parse_header(contents, path);
  MeshData data;

  const PlyElement* vertex_el = nullptr;
  const PlyElement* face_el = nullptr;
  for (const auto& e : h.elements) {
    if (e.name == "vertex" && !vertex_el) vertex_el = &e;
    if (e.name == "face" && !face_el) face_el = &e;
  }
  auto header_fail = [&](int line, const std::string& msg) -> void {
    throw IoError(path + ":" + std::to_string(line) + ": " + msg);
  };
  if (!vertex_el) header_fail(h.body_line - 1, "no 'element vertex', expected a vertex element with x, y, z");
  if (vertex_el->count > 2147483647LL) header_fail(vertex_el->line, "too many vertices");

  // Plans: what to do with each property.
  std::vector<ElementPlan> plans(h.elements.size());
  std::vector<std::string> ignored_vertex_props, ignored_face_props, ignored_elements;
  for (std::size_t i = 0; i < h.elements.size(); ++i) {
    const PlyElement& e = h.elements[i];
    ElementPlan& plan = plans[i];
    plan.slots.assign(e.props.size(), Slot::Skip);
    if (&e == vertex_el) {
      int found = 0;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        Slot s = Slot::Skip;
        if (p.name == "x") s = Slot::X;
        else if (p.name == "y") s = Slot::Y;
        else if (p.name == "z") s = Slot::Z;
        else if (p.name == "ref") s = Slot::VertexRef;
        if (s != Slot::Skip && p.is_list)
          header_fail(e.line, "vertex property '" + p.name + "' is a list, expected a scalar");
        if (s == Slot::X || s == Slot::Y || s == Slot::Z) found |= 1 << (static_cast<int>(s) - 1);
        if (s == Slot::Skip) ignored_vertex_props.push_back(p.name);
        plan.slots[k] = s;
      }
      if (found != 7) header_fail(e.line, "element vertex lacks property x, y or z, expected all three");
    } else if (&e == face_el) {
      bool have_indices = false;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        if ((p.name == "vertex_indices" || p.name == "vertex_index") && !have_indices) {
          if (!p.is_list) header_fail(e.line, "face property '" + p.name + "' is not a list, expected a list");
          if (!is_integer(p.type))
            header_fail(e.line, "face property '" + p.name + "' has a floating-point item type, expected an integer");
          plan.slots[k] = Slot::Indices;
          have_indices = true;
        } else if (p.name == "ref" && !p.is_list) {
          plan.slots[k] = Slot::FaceRef;
        } else {
          ignored_face_props.push_back(p.name);
        }
      }
      if (!have_indices)
        header_fail(e.line, "element face has no list property vertex_indices, expected "
                            "'property list uchar int vertex_indices'");
    } else {
      ignored_elements.push_back(e.name);
    }
  }

  const long long nv = vertex_el->count;
  bool have_vref = false, have_fref = false;
  for (std::size_t k = 0; k < vertex_el->props.size(); ++k) have_vref |= plans[vertex_el - h.elements.data()].slots[k] == Slot::VertexRef;
  if (face_el)
    for (std::size_t k = 0; k < face_el->props.size(); ++k) have_fref |= plans[face_el - h.elements.data()].slots[k] == Slot::FaceRef;

  // Element counts against the bytes left, before reserving anything.
  const std::size_t remaining = contents.size() - h.body_offset;
  for (const auto& e : h.elements) {
    std::size_t per = h.format == PlyFormat::Ascii ? 2 * e.props.size() : e.min_binary_size();
    if (per > 0 && static_cast<unsigned long long>(e.count) > remaining / per) {
      std::string msg = "element " + e.name + " announces " + std::to_string(e.count) +
                        " entries but only " + std::to_string(remaining) + " bytes of data follow the header (at least " +
                        std::to_string(per) + " per entry expected)";
      header_fail(e.line, msg);
    }
  }
  data.vertices.resize(static_cast<std::size_t>(nv));
  if (have_vref) data.vertex_refs.assign(static_cast<std::size_t>(nv), 0);
  if (face_el) data.triangles.reserve(static_cast<std::size_t>(face_el->count));

  std::vector<int> poly;
  auto to_int = [](double v) { return static_cast<int>(std::clamp(v, -2147483648.0, 2147483647.0)); };

  if (h.format == PlyFormat::Ascii) {
    TextReader r(std::move(contents), path, '\0');
    for (int l = 1; l < h.body_line; ++l) r.rest_of_line();
    for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
      const PlyElement& e = h.elements[ei];
      const ElementPlan& plan = plans[ei];
      for (long long i = 0; i < e.count; ++i) {
        double face_ref = 0;
        bool face = &e == face_el;
        if (face) poly.clear();
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const PlyProperty& p = e.props[k];
          Slot s = plan.slots[k];
          if (p.is_list) {
            long long n = r.read_int("list count (integer)");
            if (n < 0 || static_cast<unsigned long long>(n) > remaining)
              r.fail("list " + p.name + " has count " + std::to_string(n) + ", expected 0.." + std::to_string(remaining));
            if (s == Slot::Indices) {
              if (n < 3)
                r.fail("face " + std::to_string(i) + " has " + std::to_string(n) + " vertices, expected at least 3");
              for (long long j = 0; j < n; ++j) {
                long long id = r.read_int("face vertex index (integer)");
                if (id < 0 || id >= nv)
                  r.fail("face " + std::to_string(i) + ": vertex index " + std::to_string(id) +
                         " out of range, expected 0.." + std::to_string(nv - 1));
                poly.push_back(static_cast<int>(id));
              }
            } else {
              for (long long j = 0; j < n; ++j) r.read_double("list value");
            }
            continue;
          }
          double v = r.read_double(p.name.c_str());
          switch (s) {
            case Slot::X:
            case Slot::Y:
            case Slot::Z:
              if (!std::isfinite(v)) r.fail("vertex " + std::to_string(i) + ": " + p.name + " is not a finite number");
              data.vertices[static_cast<std::size_t>(i)][static_cast<int>(s) - 1] = v;
              break;
            case Slot::VertexRef: data.vertex_refs[static_cast<std::size_t>(i)] = to_int(v); break;
            case Slot::FaceRef: face_ref = v; break;
            default: break;
          }
        }
        if (face) {
          for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            data.triangles.push_back({poly[0], poly[k], poly[k + 1]});
            if (have_fref) data.triangle_refs.push_back(to_int(face_ref));
          }
        }
      }
    }
  } else {
    const bool file_little = h.format == PlyFormat::BinaryLittle;
    const bool swap = file_little != host_is_little_endian();
    ByteReader b(std::move(contents), path);
    b.seek(h.body_offset);
    for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
      const PlyElement& e = h.elements[ei];
      const ElementPlan& plan = plans[ei];
      const bool face = &e == face_el;
      // Other elements made of scalars only: skip them in one step.
      if (&e != vertex_el && !face) {
        bool fixed = std::none_of(e.props.begin(), e.props.end(), [](const PlyProperty& p) { return p.is_list; });
        if (fixed) {
          b.bytes(static_cast<std::size_t>(e.count) * e.min_binary_size(), ("element " + e.name).c_str());
          continue;
        }
      }
      for (long long i = 0; i < e.count; ++i) {
        double face_ref = 0;
        if (face) poly.clear();
        for (std::size_t k = 0; k < e.props.size(); ++k) {
          const PlyProperty& p = e.props[k];
          Slot s = plan.slots[k];
          if (p.is_list) {
            const std::size_t at = b.offset();
            double nd = read_binary(b, p.count_type, swap, "list count");
            long long n = static_cast<long long>(nd);
            if (n < 0) {
              b.seek(at);
              b.fail("list " + p.name + " has negative count " + std::to_string(n) + ", expected >= 0");
            }
            if (s == Slot::Indices) {
              if (n < 3) {
                b.seek(at);
                b.fail("face " + std::to_string(i) + " has " + std::to_string(n) + " vertices, expected at least 3");
              }
              for (long long j = 0; j < n; ++j) {
                const std::size_t at_id = b.offset();
                double idd = read_binary(b, p.type, swap, "face vertex index");
                long long id = static_cast<long long>(idd);
                if (id < 0 || id >= nv) {
                  b.seek(at_id);
                  b.fail("face " + std::to_string(i) + ": vertex index " + std::to_string(id) +
                         " out of range, expected 0.." + std::to_string(nv - 1));
                }
                poly.push_back(static_cast<int>(id));
              }
            } else {
              const std::size_t item = type_size(p.type);
              if (static_cast<unsigned long long>(n) > (b.size() - b.offset()) / item) {
                b.seek(at);
                b.fail("list " + p.name + " announces " + std::to_string(n) + " items but only " +
                       std::to_string(b.size() - at) + " bytes remain, expected a smaller count");
              }
              b.bytes(static_cast<std::size_t>(n) * item, "list items");
            }
            continue;
          }
          if (s == Slot::Skip) {
            b.bytes(type_size(p.type), p.name.c_str());
            continue;
          }
          const std::size_t at = b.offset();
          double v = read_binary(b, p.type, swap, p.name.c_str());
          switch (s) {
            case Slot::X:
            case Slot::Y:
            case Slot::Z:
              if (!std::isfinite(v)) {
                b.seek(at);
                b.fail("vertex " + std::to_string(i) + ": " + p.name + " is not a finite number");
              }
              data.vertices[static_cast<std::size_t>(i)][static_cast<int>(s) - 1] = v;
              break;
            case Slot::VertexRef: data.vertex_refs[static_cast<std::size_t>(i)] = to_int(v); break;
            case Slot::FaceRef: face_ref = v; break;
            default: break;
          }
        }
        if (face) {
          for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
            data.triangles.push_back({poly[0], poly[k], poly[k + 1]});
            if (have_fref) data.triangle_refs.push_back(to_int(face_ref));
          }
        }
      }
    }
    if (!b.at_end())
      data.warnings.push_back(path + ": ignored " + std::to_string(b.size() - b.offset()) +
                              " bytes after the last element (byte " + std::to_string(b.offset()) + ")");
  }

  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  if (!ignored_vertex_props.empty())
    data.warnings.push_back(path + ": ignored vertex properties: " + join(ignored_vertex_props));
  if (!ignored_face_props.empty())
    data.warnings.push_back(path + ": ignored face properties: " + join(ignored_face_props));
  if (!ignored_elements.empty()) data.warnings.push_back(path + ": ignored elements: " + join(ignored_elements));
  if (!face_el) data.warnings.push_back(path + ": no 'element face': the file has no triangles");
  return data;
}

void write_ply(const std::string& path, const MeshData& data, bool binary, bool big_endian) {
  const std::size_t nv = data.vertices.size();
  const std::size_t nt = data.triangles.size();
  for (std::size_t t = 0; t < nt; ++t)
    for (int id : data.triangles[t])
      if (id < 0 || static_cast<std::size_t>(id) >= nv)
        throw IoError(path + ": cannot write: triangle " + std::to_string(t) + " has vertex id " +
                      std::to_string(id) + ", expected 0.." + std::to_string(static_cast<long long>(nv) - 1));
  const bool vref = !data.vertex_refs.empty();
  const bool fref = !data.triangle_refs.empty();
  if (vref && data.vertex_refs.size() != nv)
    throw IoError(path + ": cannot write: " + std::to_string(data.vertex_refs.size()) + " vertex references for " +
                  std::to_string(nv) + " vertices");
  if (fref && data.triangle_refs.size() != nt)
    throw IoError(path + ": cannot write: " + std::to_string(data.triangle_refs.size()) +
                  " triangle references for " + std::to_string(nt) + " triangles");

  std::string out;
  out += "ply\nformat ";
  out += !binary ? "ascii" : (big_endian ? "binary_big_endian" : "binary_little_endian");
  out += " 1.0\ncomment written by anisurf\n";
  out += "element vertex " + std::to_string(nv) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  if (vref) out += "property int ref\n";
  out += "element face " + std::to_string(nt) + "\n";
  out += "property list uchar int vertex_indices\n";
  if (fref) out += "property int ref\n";
  out += "end_header\n";

  if (!binary) {
    out.reserve(out.size() + nv * 48 + nt * 24);
    for (std::size_t i = 0; i < nv; ++i) {
      const Vec3& p = data.vertices[i];
      append_double(out, p.x);
      out += ' ';
      append_double(out, p.y);
      out += ' ';
      append_double(out, p.z);
      if (vref) {
        out += ' ';
        out += std::to_string(data.vertex_refs[i]);
      }
      out += '\n';
    }
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& tri = data.triangles[t];
      out += "3 " + std::to_string(tri[0]) + ' ' + std::to_string(tri[1]) + ' ' + std::to_string(tri[2]);
      if (fref) out += ' ' + std::to_string(data.triangle_refs[t]);
      out += '\n';
    }
  } else {
    const bool swap = big_endian == host_is_little_endian();
    auto put = [&](const auto& v) {
      char bytes[sizeof v];
      std::memcpy(bytes, &v, sizeof v);
      if (swap) std::reverse(bytes, bytes + sizeof v);
      out.append(bytes, sizeof v);
    };
    out.reserve(out.size() + nv * (24 + 4) + nt * (13 + 4));
    for (std::size_t i = 0; i < nv; ++i) {
      const Vec3& p = data.vertices[i];
      put(p.x);
      put(p.y);
      put(p.z);
      if (vref) put(static_cast<std::int32_t>(data.vertex_refs[i]));
    }
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& tri = data.triangles[t];
      put(static_cast<std::uint8_t>(3));
      for (int id : tri) put(static_cast<std::int32_t>(id));
      if (fref) put(static_cast<std::int32_t>(data.triangle_refs[t]));
    }
  }
  AtomicFile file(path);
  file.stream().write(out.data(), static_cast<std::streamsize>(out.size()));
  file.commit();
}

}  // namespace anisurf::io
