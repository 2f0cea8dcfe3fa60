// Wavefront OBJ: geometry only. Reads `v` and `f` (polygons fan-triangulated),
// ignores the other statements; writes `v` (shortest round-trip doubles) and
// `f` (1-based).
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/formats.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

// Statements that carry no geometry we use: skipped silently.
bool is_ignored_statement(std::string_view k) {
  return k == "vt" || k == "vn" || k == "vp" || k == "g" || k == "o" || k == "s" || k == "usemtl" ||
         k == "mtllib" || k == "l" || k == "p" || k == "usemap" || k == "maplib" || k == "lod" || k == "shadow_obj" ||
         k == "trace_obj" || k == "bevel" || k == "c_interp" || k == "d_interp";
}

// Index of a face corner "a", "a/b", "a//c" or "a/b/c" (the vertex part only),
// as a 0-based id; negative indices count back from the last vertex read.
// `forward` receives true for a positive index beyond the vertices read so
// far (checked once the whole file is read).
int corner_vertex(const TextReader& r, std::string_view tok, int n_vertices, bool& forward) {
  std::size_t slash = tok.find('/');
  std::string_view head = tok.substr(0, slash);
  if (slash != std::string_view::npos) {
    std::string_view rest = tok.substr(slash + 1);
    std::size_t slash2 = rest.find('/');
    if (slash2 != std::string_view::npos && rest.find('/', slash2 + 1) != std::string_view::npos)
      r.fail_expected("face corner 'v', 'v/vt', 'v//vn' or 'v/vt/vn'", tok);
  }
  long long v = 0;
  const char* b = head.data();
  const char* e = b + head.size();
  if (b != e && *b == '+') ++b;
  auto res = std::from_chars(b, e, v);
  if (head.empty() || res.ec != std::errc() || res.ptr != e)
    r.fail_expected("face vertex index (integer, 1-based)", tok);
  forward = false;
  if (v == 0) r.fail("face vertex index 0: OBJ indices start at 1 (or count back from -1)");
  if (v < 0) {
    if (-v > n_vertices)
      r.fail("face vertex index " + std::to_string(v) + " out of range: only " + std::to_string(n_vertices) +
             " vertices before this line, expected -" + std::to_string(n_vertices) + "..-1");
    return n_vertices + static_cast<int>(v);
  }
  if (v > 2147483647LL) r.fail("face vertex index " + std::to_string(v) + " out of range");
  forward = v > n_vertices;
  return static_cast<int>(v - 1);
}

}  // namespace

MeshData read_obj(const std::string& path) {
  TextReader r(path, '#');
  MeshData data;
  std::vector<int> poly;
  std::string_view tok;
  // First face line referring to a vertex defined later (legal but rare):
  // checked against the final vertex count.
  int forward_line = 0;
  int forward_max = 0;
  int unknown_count = 0;
  std::string unknown_first;
  int unknown_line = 0;

  while (!r.at_end()) {
    r.next_on_line(tok);
    if (tok == "v") {
      double c[3];
      static const char* names[3] = {"vertex x coordinate", "vertex y coordinate", "vertex z coordinate"};
      for (int k = 0; k < 3; ++k) {
        std::string_view t;
        if (!r.next_on_line(t)) r.fail(std::string("expected ") + names[k] + " at the end of the line");
        c[k] = r.parse_double(t, names[k]);
        if (!std::isfinite(c[k])) r.fail(std::string(names[k]) + " is not a finite number ('" + std::string(t) + "')");
      }
      data.vertices.emplace_back(c[0], c[1], c[2]);
      r.rest_of_line();  // optional w or vertex colours
    } else if (tok == "f") {
      poly.clear();
      const int nv = static_cast<int>(data.vertices.size());
      std::string_view t;
      while (r.next_on_line(t)) {
        bool forward = false;
        int id = corner_vertex(r, t, nv, forward);
        if (forward) {
          if (forward_line == 0) forward_line = r.line();
          forward_max = std::max(forward_max, id + 1);
        }
        poly.push_back(id);
      }
      if (poly.size() < 3)
        r.fail("face with " + std::to_string(poly.size()) + " vertices, expected at least 3");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) data.triangles.push_back({poly[0], poly[k], poly[k + 1]});
      r.rest_of_line();
    } else {
      if (!is_ignored_statement(tok)) {
        if (unknown_count++ == 0) {
          unknown_first = std::string(tok.substr(0, 40));
          unknown_line = r.line();
        }
      }
      r.rest_of_line();
    }
  }
  if (forward_max > static_cast<int>(data.vertices.size()))
    throw IoError(path + ":" + std::to_string(forward_line) + ": face vertex index out of range (up to " +
                  std::to_string(forward_max) + "), expected 1.." + std::to_string(data.vertices.size()));
  if (unknown_count > 0)
    data.warnings.push_back(path + ": ignored " + std::to_string(unknown_count) +
                            " line(s) of unknown OBJ statement type (first: '" + unknown_first + "' at line " +
                            std::to_string(unknown_line) + ")");
  return data;
}

void write_obj(const std::string& path, const MeshData& data) {
  const std::size_t nv = data.vertices.size();
  for (std::size_t t = 0; t < data.triangles.size(); ++t)
    for (int id : data.triangles[t])
      if (id < 0 || static_cast<std::size_t>(id) >= nv)
        throw IoError(path + ": cannot write: triangle " + std::to_string(t) + " has vertex id " +
                      std::to_string(id) + ", expected 0.." + std::to_string(static_cast<long long>(nv) - 1));
  AtomicFile file(path);
  std::string out;
  out.reserve(nv * 40 + data.triangles.size() * 24 + 64);
  out += "# written by anisurf\n";
  for (const Vec3& p : data.vertices) {
    out += "v ";
    append_double(out, p.x);
    out += ' ';
    append_double(out, p.y);
    out += ' ';
    append_double(out, p.z);
    out += '\n';
  }
  char buf[16];
  for (const auto& t : data.triangles) {
    out += 'f';
    for (int id : t) {
      out += ' ';
      auto res = std::to_chars(buf, buf + sizeof buf, id + 1);
      out.append(buf, res.ptr);
    }
    out += '\n';
  }
  file.stream().write(out.data(), static_cast<std::streamsize>(out.size()));
  file.commit();
}

}  // namespace anisurf::io
