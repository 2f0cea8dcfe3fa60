// Object File Format (OFF), reading only. Header keyword [ST][C][N]OFF, then
// "nv nf ne", nv vertex lines (x y z, then optional texture coordinates,
// colour or normal values which are ignored), nf face lines (n i1 .. in, then
// optional colour values which are ignored). Polygons are fan-triangulated.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "io/formats.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

// Skips the remaining values of the current line (colours, normals ...).
void skip_line_values(TextReader& r) {
  std::string_view t;
  while (r.next_on_line(t)) {
  }
}

}  // namespace

MeshData read_off(const std::string& path) {
  std::string contents = read_file_contents(path);
  const std::size_t file_size = contents.size();
  TextReader r(std::move(contents), path, '#');
  MeshData data;

  std::string_view head = r.token("OFF header keyword");
  // Prefixes: ST (texture coordinates), C (colours), N (normals), 4 (4D), n (nD).
  std::string_view kw = head;
  std::string_view counts_inline;  // "OFF8 6 0" (no blank after the keyword)
  std::size_t off_at = kw.find("OFF");
  if (off_at == std::string_view::npos) r.fail_expected("OFF header ('OFF', 'COFF', 'NOFF', 'CNOFF' or 'STOFF')", head);
  std::string_view prefix = kw.substr(0, off_at);
  counts_inline = kw.substr(off_at + 3);
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    char c = prefix[i];
    if (c == 'S' && i + 1 < prefix.size() && prefix[i + 1] == 'T') {
      ++i;
    } else if (c == 'C' || c == 'N') {
    } else if (c == '4' || c == 'n') {
      std::string msg(head);
      msg += ": 4D and nD OFF files are not supported, expected a 3D OFF file";
      r.fail(msg);
    } else {
      r.fail_expected("OFF header ('OFF', 'COFF', 'NOFF', 'CNOFF' or 'STOFF')", head);
    }
  }

  long long nv = 0;
  if (!counts_inline.empty()) {
    nv = r.parse_int(counts_inline, "vertex count");
  } else {
    nv = r.read_int("vertex count");
  }
  long long nf = r.read_int("face count");
  long long ne = r.read_int("edge count");
  // Each vertex needs at least 6 bytes ("0 0 0\n"), each face 8 ("3 0 1 2\n").
  if (nv < 0 || nv > static_cast<long long>(file_size / 6) + 1)
    r.fail("vertex count " + std::to_string(nv) + " impossible for a file of " + std::to_string(file_size) +
           " bytes, expected 0.." + std::to_string(file_size / 6));
  if (nf < 0 || nf > static_cast<long long>(file_size / 8) + 1)
    r.fail("face count " + std::to_string(nf) + " impossible for a file of " + std::to_string(file_size) +
           " bytes, expected 0.." + std::to_string(file_size / 8));
  if (ne < 0) r.fail("edge count " + std::to_string(ne) + " is negative, expected >= 0");
  skip_line_values(r);

  data.vertices.reserve(static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (r.at_end())
      r.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
             " vertices, expected more vertex lines (the header announces more vertices than the file has)");
    double c[3];
    for (int k = 0; k < 3; ++k) {
      std::string_view t;
      if (k == 0) {
        t = r.token("vertex x coordinate");
      } else if (!r.next_on_line(t)) {
        r.fail("vertex " + std::to_string(i) + ": expected 3 coordinates on the line, found " + std::to_string(k));
      }
      c[k] = r.parse_double(t, "vertex coordinate");
      if (!std::isfinite(c[k]))
        r.fail("vertex " + std::to_string(i) + ": coordinate '" + std::string(t) + "' is not a finite number");
    }
    data.vertices.emplace_back(c[0], c[1], c[2]);
    skip_line_values(r);
  }

  data.triangles.reserve(static_cast<std::size_t>(nf));
  std::vector<int> poly;
  for (long long f = 0; f < nf; ++f) {
    if (r.at_end())
      r.fail("file ends after " + std::to_string(f) + " of " + std::to_string(nf) +
             " faces, expected more face lines (fewer vertices or faces than the header announces?)");
    std::string_view t = r.token("face vertex count");
    long long n = r.parse_int(t, "face vertex count (integer)");
    if (n < 3) r.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " vertices, expected at least 3");
    if (n > nv) r.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " vertices, more than the file's " +
                       std::to_string(nv) + " vertices");
    poly.clear();
    for (long long k = 0; k < n; ++k) {
      if (!r.next_on_line(t))
        r.fail("face " + std::to_string(f) + ": expected " + std::to_string(n) + " vertex indices on the line, found " +
               std::to_string(k));
      long long id = r.parse_int(t, "face vertex index (integer)");
      if (id < 0 || id >= nv)
        r.fail("face " + std::to_string(f) + ": vertex index " + std::to_string(id) + " out of range, expected 0.." +
               std::to_string(nv - 1));
      poly.push_back(static_cast<int>(id));
    }
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) data.triangles.push_back({poly[0], poly[k], poly[k + 1]});
    skip_line_values(r);  // face colour
  }
  if (!r.at_end()) {
    std::string_view t = r.token("end of file");
    data.warnings.push_back(path + ":" + std::to_string(r.line()) + ": ignored data after the last face ('" +
                            std::string(t.substr(0, 40)) + "')");
  }
  return data;
}

}  // namespace anisurf::io
