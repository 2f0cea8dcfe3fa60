// STL, ASCII and binary. A file is binary when its size is 84 + 50 n for the
// facet count n stored at byte 80 (binary files may begin with "solid"), else
// ASCII when it begins with "solid". Every facet gives 3 new vertices
// (split_vertices: build_mesh merges them).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/formats.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

bool starts_with_solid(const std::string& d) {
  std::size_t p = 0;
  while (p < d.size() && std::isspace(static_cast<unsigned char>(d[p]))) ++p;
  return d.size() - p >= 5 && iequals(std::string_view(d).substr(p, 5), "solid");
}

void expect_keyword(TextReader& r, const char* kw, const char* context) {
  std::string_view t;
  if (!r.next(t)) r.fail(std::string("unexpected end of file, expected '") + kw + "' " + context);
  if (!iequals(t, kw)) r.fail(std::string("expected '") + kw + "' " + context + ", found '" + std::string(t.substr(0, 40)) + "'");
}

MeshData read_stl_ascii(std::string contents, const std::string& path) {
  TextReader r(std::move(contents), path, '\0');
  MeshData data;
  data.split_vertices = true;
  std::string_view t;
  r.token("'solid'");  // checked by the caller
  r.rest_of_line();    // solid name
  bool ended = false;
  while (r.next(t)) {
    if (iequals(t, "endsolid")) {
      r.rest_of_line();
      ended = true;
      // Several solids may follow each other.
      if (r.at_end()) break;
      expect_keyword(r, "solid", "after 'endsolid'");
      r.rest_of_line();
      ended = false;
      continue;
    }
    if (!iequals(t, "facet"))
      r.fail("expected 'facet' or 'endsolid', found '" + std::string(t.substr(0, 40)) + "'");
    expect_keyword(r, "normal", "after 'facet'");
    for (int k = 0; k < 3; ++k) r.read_double("facet normal component");
    expect_keyword(r, "outer", "(start of 'outer loop')");
    expect_keyword(r, "loop", "after 'outer'");
    const int base = static_cast<int>(data.vertices.size());
    for (int v = 0; v < 3; ++v) {
      expect_keyword(r, "vertex", v == 0 ? "(3 vertices per facet)" : "(3 vertices per facet, found fewer)");
      double c[3];
      for (int k = 0; k < 3; ++k) {
        c[k] = r.read_double("vertex coordinate");
        if (!std::isfinite(c[k])) r.fail("vertex coordinate is not a finite number");
      }
      data.vertices.emplace_back(c[0], c[1], c[2]);
    }
    expect_keyword(r, "endloop", "after the 3 vertices of a facet");
    expect_keyword(r, "endfacet", "after 'endloop'");
    data.triangles.push_back({base, base + 1, base + 2});
  }
  if (!ended) data.warnings.push_back(path + ": no 'endsolid' at the end of the file");
  return data;
}

MeshData read_stl_binary(ByteReader& b, std::uint32_t n) {
  MeshData data;
  data.split_vertices = true;
  const bool swap = !host_is_little_endian();
  data.vertices.reserve(3 * static_cast<std::size_t>(n));
  data.triangles.reserve(n);
  b.seek(84);
  for (std::uint32_t f = 0; f < n; ++f) {
    b.bytes(12, "facet normal");
    const int base = static_cast<int>(data.vertices.size());
    for (int v = 0; v < 3; ++v) {
      const std::size_t at = b.offset();
      float c[3];
      for (float& x : c) x = b.read<float>("facet vertex", swap);
      for (float x : c)
        if (!std::isfinite(x)) {
          b.seek(at);
          b.fail("facet " + std::to_string(f) + ": vertex coordinate is not a finite number, expected finite floats");
        }
      data.vertices.emplace_back(c[0], c[1], c[2]);
    }
    b.bytes(2, "facet attribute byte count");
    data.triangles.push_back({base, base + 1, base + 2});
  }
  return data;
}

}  // namespace

MeshData read_stl(const std::string& path) {
  ByteReader b = ByteReader::from_file(path);
  const std::size_t size = b.size();
  if (size >= 84) {
    b.seek(80);
    const std::uint32_t n = b.read<std::uint32_t>("facet count", !host_is_little_endian());
    const unsigned long long expected = 84ull + 50ull * n;
    if (expected == size) {
      if (3ull * n > 2147483647ull) b.fail("too many facets (" + std::to_string(n) + ")");
      return read_stl_binary(b, n);
    }
    if (!starts_with_solid(b.data())) {
      b.seek(80);
      if (expected > size)
        b.fail("truncated binary STL: the header announces " + std::to_string(n) + " facets, expected " +
               std::to_string(expected) + " bytes but the file has " + std::to_string(size));
      b.fail("binary STL size mismatch: the header announces " + std::to_string(n) + " facets, expected " +
             std::to_string(expected) + " bytes but the file has " + std::to_string(size) +
             " (and it does not begin with 'solid', so it is not ASCII STL)");
    }
  } else if (!starts_with_solid(b.data())) {
    b.seek(0);
    b.fail("file of " + std::to_string(size) +
           " bytes: too short for binary STL (84 bytes at least) and not ASCII STL, expected 'solid' at the start");
  }
  return read_stl_ascii(b.data(), path);
}

void write_stl(const std::string& path, const MeshData& data, bool binary) {
  const std::size_t nv = data.vertices.size();
  const std::size_t nt = data.triangles.size();
  for (std::size_t t = 0; t < nt; ++t)
    for (int id : data.triangles[t])
      if (id < 0 || static_cast<std::size_t>(id) >= nv)
        throw IoError(path + ": cannot write: triangle " + std::to_string(t) + " has vertex id " +
                      std::to_string(id) + ", expected 0.." + std::to_string(static_cast<long long>(nv) - 1));
  if (nt > 0xffffffffull) throw IoError(path + ": cannot write: too many triangles for binary STL");
  for (std::size_t i = 0; i < nv; ++i) {
    const Vec3& p = data.vertices[i];
    if (!std::isfinite(static_cast<float>(p.x)) || !std::isfinite(static_cast<float>(p.y)) ||
        !std::isfinite(static_cast<float>(p.z)))
      throw IoError(path + ": cannot write: vertex " + std::to_string(i) +
                    " has a coordinate that is not finite in float precision, expected |x| < 3.4e38");
  }

  auto facet_normal = [&](const std::array<int, 3>& tri) {
    const Vec3& a = data.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = data.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = data.vertices[static_cast<std::size_t>(tri[2])];
    return normalized(cross(b - a, c - a));
  };

  std::string out;
  if (binary) {
    out.reserve(84 + 50 * nt);
    std::string header = "anisurf binary STL";  // must not begin with "solid"
    header.resize(80, ' ');
    out += header;
    const bool swap = !host_is_little_endian();
    auto put = [&](const auto& v) {
      char bytes[sizeof v];
      std::memcpy(bytes, &v, sizeof v);
      if (swap) std::reverse(bytes, bytes + sizeof v);
      out.append(bytes, sizeof v);
    };
    put(static_cast<std::uint32_t>(nt));
    for (const auto& tri : data.triangles) {
      Vec3 n = facet_normal(tri);
      put(static_cast<float>(n.x));
      put(static_cast<float>(n.y));
      put(static_cast<float>(n.z));
      for (int id : tri) {
        const Vec3& p = data.vertices[static_cast<std::size_t>(id)];
        put(static_cast<float>(p.x));
        put(static_cast<float>(p.y));
        put(static_cast<float>(p.z));
      }
      put(static_cast<std::uint16_t>(0));
    }
  } else {
    auto f = [](double v) { return format_double(static_cast<double>(static_cast<float>(v))); };
    out.reserve(32 + nt * 260);
    out += "solid anisurf\n";
    for (const auto& tri : data.triangles) {
      Vec3 n = facet_normal(tri);
      out += "  facet normal " + f(n.x) + ' ' + f(n.y) + ' ' + f(n.z) + "\n    outer loop\n";
      for (int id : tri) {
        const Vec3& p = data.vertices[static_cast<std::size_t>(id)];
        out += "      vertex " + f(p.x) + ' ' + f(p.y) + ' ' + f(p.z) + '\n';
      }
      out += "    endloop\n  endfacet\n";
    }
    out += "endsolid anisurf\n";
  }
  AtomicFile file(path);
  file.stream().write(out.data(), static_cast<std::streamsize>(out.size()));
  file.commit();
}

}  // namespace anisurf::io
