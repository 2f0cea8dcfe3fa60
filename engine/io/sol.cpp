// Medit solution files: ASCII .sol and binary .solb (GMF), section
// SolAtVertices with one or several fields per file. Types: 1 scalar,
// 2 vector (dim components), 3 symmetric tensor (3 components in 2D, 6 in 3D,
// in the file order m11 m12 m22 m13 m23 m33, kept as is in FieldData::values).
//
// Field names are not part of the format: fields are named "sol0", "sol1" ...
// The ASCII writer keeps other names in a comment line
// "# anisurf field names: a b" that the ASCII reader reads back (readers of
// the format skip comments).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
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

// GMF keyword codes (libMeshb).
constexpr int kGmfDimension = 3;
constexpr int kGmfEnd = 54;
constexpr int kGmfSolAtVertices = 62;
constexpr int kMaxFields = 1000;  // libMeshb's GmfMaxTyp
constexpr std::string_view kNamesTag = "anisurf field names:";

// Components of a solution type in a dimension (0 for an unsupported type).
int type_components(long long type, int dim) {
  switch (type) {
    case 1: return 1;
    case 2: return dim;
    case 3: return dim * (dim + 1) / 2;
    default: return 0;
  }
}

std::string type_message(long long type) {
  std::string m = type == 4 ? "solution type 4 (full matrix) unsupported"
                            : "unknown solution type " + std::to_string(type);
  return m + ", expected 1 (scalar), 2 (vector) or 3 (symmetric tensor)";
}

std::string default_name(std::size_t k) { return "sol" + std::to_string(k); }

// Fields of a SolAtVertices section with `types`, values not yet filled
// (memory reserved for at most `max_values` values in all, a bound given by
// the file size so that a corrupt count cannot exhaust memory).
std::vector<FieldData> make_fields(const std::vector<int>& types, int dim, long long n, std::size_t first,
                                   std::size_t max_values) {
  std::vector<FieldData> out;
  std::size_t comps = 0;
  for (int t : types) comps += static_cast<std::size_t>(type_components(t, dim));
  const std::size_t vertices = std::min(static_cast<std::size_t>(n), max_values / std::max<std::size_t>(comps, 1));
  for (std::size_t k = 0; k < types.size(); ++k) {
    FieldData f;
    f.info.name = default_name(first + k);
    f.info.kind = static_cast<FieldKind>(types[k]);
    f.info.ncomp = type_components(types[k], dim);
    reserve_huge(f.values, vertices * static_cast<std::size_t>(f.info.ncomp));
    out.push_back(std::move(f));
  }
  return out;
}

std::string count_mismatch(long long count, int n_vertices) {
  return std::to_string(count) + " values but the mesh has " + std::to_string(n_vertices) +
         " vertices (expected one value per vertex)";
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

// Names from a "# anisurf field names: a b c" comment line (empty if none).
std::vector<std::string> names_from_comment(const std::string& text) {
  std::vector<std::string> names;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    std::size_t i = line.find_first_not_of(" \t");
    if (i != std::string_view::npos && line[i] == '#') {
      line.remove_prefix(i + 1);
      i = line.find_first_not_of(" \t");
      if (i != std::string_view::npos && line.substr(i).starts_with(kNamesTag)) {
        line.remove_prefix(i + kNamesTag.size());
        std::size_t p = 0;
        while (p < line.size()) {
          p = line.find_first_not_of(" \t\r", p);
          if (p == std::string_view::npos) break;
          std::size_t q = line.find_first_of(" \t\r", p);
          if (q == std::string_view::npos) q = line.size();
          names.emplace_back(line.substr(p, q - p));
          p = q;
        }
        return names;
      }
    } else if (i != std::string_view::npos && std::isalpha(static_cast<unsigned char>(line[i])) &&
               iequals(line.substr(i, 13), "SolAtVertices")) {
      break;  // the comment comes before the data
    }
    pos = end + 1;
  }
  return names;
}

// --- ASCII reader ------------------------------------------------------------

class AsciiSolReader {
 public:
  AsciiSolReader(std::string contents, const std::string& path, int n_vertices)
      : names_(names_from_comment(contents)),
        max_values_(contents.size() / 2),
        in_(std::move(contents), path, '#'),
        n_vertices_(n_vertices) {}

  std::vector<FieldData> run(int* dimension) {
    std::string_view t;
    if (!in_.next(t)) in_.fail("empty file, expected 'MeshVersionFormatted'");
    if (!iequals(t, "MeshVersionFormatted"))
      in_.fail("expected 'MeshVersionFormatted' at the start of a Medit solution file, found " + quoted(t));
    const long long version = header_int("MeshVersionFormatted", "a version 1, 2, 3 or 4");
    if (version < 1 || version > 4)
      in_.fail("MeshVersionFormatted " + std::to_string(version) + " unsupported, expected 1, 2, 3 or 4");
    bool got = in_.next(t);
    while (got) {
      if (iequals(t, "End")) break;
      if (iequals(t, "Dimension")) {
        if (dim_) in_.fail("second Dimension, expected it once");
        const long long d = header_int("Dimension", "the dimension 2 or 3");
        if (d != 2 && d != 3) in_.fail("Dimension " + std::to_string(d) + " unsupported, expected 2 or 3");
        dim_ = static_cast<int>(d);
      } else if (iequals(t, "SolAtVertices")) {
        if (!dim_) in_.fail("SolAtVertices before 'Dimension', expected 'Dimension 2' or 'Dimension 3' first");
        read_sol_at_vertices();
      } else if (iequals(t, "MeshVersionFormatted")) {
        in_.fail("second MeshVersionFormatted, expected it once");
      } else {
        double x;
        if (parse_real(t, x))
          in_.fail("expected a keyword, found the number " + quoted(t) +
                   " (more values than the count of the section before?)");
        // Another section (solutions at triangles, tetrahedra ...): skipped.
        while ((got = in_.next(t)) && !is_keyword(t)) {
        }
        continue;
      }
      got = in_.next(t);
    }
    if (!seen_) in_.fail("no SolAtVertices section, expected one");
    if (names_.size() == fields_.size())
      for (std::size_t k = 0; k < names_.size(); ++k) fields_[k].info.name = names_[k];
    if (dimension) *dimension = dim_;
    return std::move(fields_);
  }

 private:
  static bool is_keyword(std::string_view t) {
    return iequals(t, "End") || iequals(t, "Dimension") || iequals(t, "SolAtVertices") ||
           iequals(t, "MeshVersionFormatted");
  }

  // At the end of the file, errors name the line of the last token.
  [[noreturn]] void fail_eof(int last_line, const std::string& message) const {
    throw IoError(in_.path() + ":" + std::to_string(last_line) + ": " + message);
  }

  long long header_int(const char* keyword, const char* what) {
    std::string_view t;
    const int last = in_.line();
    if (!in_.next(t)) fail_eof(last, std::string(keyword) + ": expected " + what + ", found the end of the file");
    long long v;
    if (!parse_integer(t, v)) in_.fail(std::string(keyword) + ": expected " + what + ", found " + quoted(t));
    return v;
  }

  void read_sol_at_vertices() {
    seen_ = true;
    const long long n = header_int("SolAtVertices", "the number of vertices (an integer)");
    if (n < 0) in_.fail("SolAtVertices: negative count " + std::to_string(n) + ", expected a count >= 0");
    if (n > INT_MAX)
      in_.fail("SolAtVertices: count " + std::to_string(n) + " too large, expected at most " + std::to_string(INT_MAX));
    if (n_vertices_ >= 0 && n != n_vertices_) in_.fail(count_mismatch(n, n_vertices_));
    if (!fields_.empty() && static_cast<long long>(fields_.front().values.size()) != n * fields_.front().info.ncomp)
      in_.fail("SolAtVertices: " + std::to_string(n) + " values, expected " +
               std::to_string(fields_.front().values.size() / static_cast<std::size_t>(fields_.front().info.ncomp)) +
               " like the section before");
    const long long nf = header_int("SolAtVertices", "the number of fields (an integer)");
    if (nf < 1 || nf > kMaxFields)
      in_.fail("SolAtVertices: " + std::to_string(nf) + " fields, expected 1.." + std::to_string(kMaxFields));
    std::vector<int> types;
    for (long long k = 0; k < nf; ++k) {
      const long long type = header_int("SolAtVertices", "a solution type 1, 2 or 3");
      if (type_components(type, dim_) == 0 || type > 3) in_.fail("SolAtVertices: " + type_message(type));
      types.push_back(static_cast<int>(type));
    }
    std::vector<FieldData> fields = make_fields(types, dim_, n, fields_.size(), max_values_);
    if (read_lines_in_parallel(fields, n)) {
      for (auto& f : fields) fields_.push_back(std::move(f));
      return;
    }
    std::string_view t;
    for (long long i = 0; i < n; ++i) {
      for (auto& f : fields) {
        for (int c = 0; c < f.info.ncomp; ++c) {
          double v;
          const int last = in_.line();
          if (!in_.next(t))
            fail_eof(last, "vertex " + std::to_string(i + 1) + ": expected a value of field " + f.info.name +
                     ", found the end of the file (SolAtVertices announced " + std::to_string(n) + ", only " +
                     std::to_string(i) + " complete: truncated file?)");
          if (!parse_real(t, v))
            in_.fail("vertex " + std::to_string(i + 1) + ": expected a value of field " + f.info.name +
                     " (a number), found " + quoted(t));
          if (!std::isfinite(v))
            in_.fail("vertex " + std::to_string(i + 1) + ": field " + f.info.name + " component " +
                     std::to_string(c + 1) + " is not finite (" + quoted(t) + "), expected a finite number");
          f.values.push_back(v);
        }
      }
    }
    for (auto& f : fields) fields_.push_back(std::move(f));
  }

  // A large section written a vertex per line (as the writers do) parsed
  // on parallel chunks: the values the reading below takes. False, with
  // nothing read, where that reading must follow (parse_lines_in_parallel)
  // or a value is one it refuses with its message.
  bool read_lines_in_parallel(std::vector<FieldData>& fields, long long n) {
    constexpr long long kMinLines = 65536;
    int tokens = 0;
    for (const auto& f : fields) tokens += f.info.ncomp;
    // A value takes 2 bytes of text at least: a count the file cannot hold
    // allocates nothing here.
    if (n < kMinLines || tokens > kMaxLineTokens || static_cast<std::size_t>(n) * tokens > max_values_) return false;
    for (auto& f : fields) f.values.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(f.info.ncomp));
    const bool taken = parse_lines_in_parallel(in_, n, tokens, kMinLines, [&](long long i, const std::string_view* token) {
      for (auto& f : fields) {
        const int nc = f.info.ncomp;
        double* out = f.values.data() + static_cast<std::size_t>(i) * static_cast<std::size_t>(nc);
        for (int c = 0; c < nc; ++c, ++token)
          if (!parse_real(*token, out[c]) || !std::isfinite(out[c])) return false;
      }
      return true;
    });
    if (!taken)
      for (auto& f : fields) f.values.clear();
    return taken;
  }

  std::vector<std::string> names_;
  std::size_t max_values_;  // a value takes at least 2 bytes of text
  TextReader in_;
  int n_vertices_;
  int dim_ = 0;
  bool seen_ = false;
  std::vector<FieldData> fields_;
};

// --- binary reader -------------------------------------------------------------

class BinarySolReader {
 public:
  BinarySolReader(const std::string& path, int n_vertices) : in_(ByteReader::from_file(path)), n_vertices_(n_vertices) {}

  std::vector<FieldData> run(int* dimension) {
    read_header();
    while (!in_.at_end()) {
      const std::size_t at = in_.offset();
      const long long code = in_.read<std::int32_t>("a keyword code", swap_);
      const std::size_t next_at = in_.offset();
      const long long next = position();
      if (code == kGmfEnd) break;
      const std::string name = code == kGmfSolAtVertices ? "SolAtVertices" : "keyword " + std::to_string(code);
      if (next != 0 && next <= static_cast<long long>(at))
        fail_at(next_at, name + " (at byte " + std::to_string(at) + "): next-keyword position " + std::to_string(next) +
                             " points backwards, expected a position after byte " + std::to_string(at));
      if (code == kGmfSolAtVertices) {
        read_sol_at_vertices(next, next_at);
      } else {
        check_next(next, next_at, name);
      }
      if (next == 0) break;
      in_.seek(static_cast<std::size_t>(next));
    }
    if (!seen_) fail_at(in_.offset(), "no SolAtVertices keyword (code 62), expected one");
    if (dimension) *dimension = dim_;
    return std::move(fields_);
  }

 private:
  [[noreturn]] void fail_at(std::size_t at, const std::string& message) {
    in_.seek(at);
    in_.fail(message);
  }
  long long position() {
    return version_ >= 3 ? in_.read<std::int64_t>("a next-keyword position", swap_)
                         : in_.read<std::int32_t>("a next-keyword position", swap_);
  }
  long long integer(const char* what) {
    return version_ >= 4 ? in_.read<std::int64_t>(what, swap_) : in_.read<std::int32_t>(what, swap_);
  }

  void read_header() {
    const long long code = in_.read<std::int32_t>("the endianness code 1");
    if (code == 1)
      swap_ = false;
    else if (code == 0x01000000)
      swap_ = true;
    else
      fail_at(0, "not a Medit binary file: expected the code 1 (or 16777216 byte-swapped), found " +
                     std::to_string(code));
    const long long v = in_.read<std::int32_t>("the version", swap_);
    if (v < 1 || v > 4) fail_at(4, ".solb version " + std::to_string(v) + " unsupported, expected 1, 2, 3 or 4");
    version_ = static_cast<int>(v);
    const long long kw = in_.read<std::int32_t>("the Dimension keyword", swap_);
    if (kw != kGmfDimension)
      fail_at(8, "expected the Dimension keyword (code 3) after the header, found keyword code " + std::to_string(kw));
    position();
    const std::size_t at = in_.offset();
    const long long d = in_.read<std::int32_t>("the dimension", swap_);
    if (d != 2 && d != 3) fail_at(at, "Dimension " + std::to_string(d) + " unsupported, expected 2 or 3");
    dim_ = static_cast<int>(d);
  }

  void check_next(long long next, std::size_t next_at, const std::string& name) {
    if (next < 0 || next > static_cast<long long>(in_.size()))
      fail_at(next_at, name + ": next-keyword position " + std::to_string(next) +
                           " is past the end of the file, expected at most " + std::to_string(in_.size()) +
                           " (truncated or corrupt file)");
  }

  void read_sol_at_vertices(long long next, std::size_t next_at) {
    if (seen_) fail_at(next_at - 4, "second SolAtVertices keyword, expected one");
    seen_ = true;
    const std::size_t count_at = in_.offset();
    const long long n = integer("the number of vertices");
    if (n < 0) fail_at(count_at, "SolAtVertices: negative count " + std::to_string(n) + ", expected a count >= 0");
    if (n > INT_MAX)
      fail_at(count_at, "SolAtVertices: count " + std::to_string(n) + " too large, expected at most " +
                            std::to_string(INT_MAX));
    if (n_vertices_ >= 0 && n != n_vertices_) fail_at(count_at, count_mismatch(n, n_vertices_));
    const std::size_t nf_at = in_.offset();
    const long long nf = in_.read<std::int32_t>("the number of fields", swap_);
    if (nf < 1 || nf > kMaxFields)
      fail_at(nf_at, "SolAtVertices: " + std::to_string(nf) + " fields, expected 1.." + std::to_string(kMaxFields));
    std::vector<int> types;
    int comps = 0;
    for (long long k = 0; k < nf; ++k) {
      const std::size_t type_at = in_.offset();
      const long long type = in_.read<std::int32_t>("a solution type", swap_);
      if (type_components(type, dim_) == 0 || type > 3) fail_at(type_at, "SolAtVertices: " + type_message(type));
      types.push_back(static_cast<int>(type));
      comps += type_components(type, dim_);
    }
    const std::size_t real_size = version_ == 1 ? 4 : 8;
    const std::size_t start = in_.offset();
    const long long bytes = n * comps * static_cast<long long>(real_size);
    if (bytes > static_cast<long long>(in_.size() - start))
      fail_at(start, "truncated file: SolAtVertices announces " + std::to_string(n) + " vertices (" +
                         std::to_string(bytes) + " bytes from byte " + std::to_string(start) + ") but the file has " +
                         std::to_string(in_.size()) + " bytes, expected at least " + std::to_string(start + bytes));
    check_next(next, next_at, "SolAtVertices");
    if (next != 0 && static_cast<long long>(start) + bytes > next)
      fail_at(next_at, "SolAtVertices: next-keyword position " + std::to_string(next) +
                           " lies inside its data, expected at least " + std::to_string(start + bytes));
    fields_ = make_fields(types, dim_, n, 0, static_cast<std::size_t>(bytes) / real_size);
    for (long long i = 0; i < n; ++i) {
      for (auto& f : fields_) {
        for (int c = 0; c < f.info.ncomp; ++c) {
          const std::size_t at = in_.offset();
          const double v = version_ == 1 ? static_cast<double>(in_.read<float>("a value", swap_))
                                         : in_.read<double>("a value", swap_);
          if (!std::isfinite(v))
            fail_at(at, "vertex " + std::to_string(i + 1) + ": field " + f.info.name + " component " +
                            std::to_string(c + 1) + " is not finite, expected a finite number");
          f.values.push_back(v);
        }
      }
    }
  }

  ByteReader in_;
  int n_vertices_;
  bool swap_ = false;
  int version_ = 2;
  int dim_ = 3;
  bool seen_ = false;
  std::vector<FieldData> fields_;
};

// --- writers ---------------------------------------------------------------------

// Checks fields before writing; returns the GMF type of each.
std::vector<int> check_fields(const std::string& path, const std::vector<FieldView>& fields, int n, int dim) {
  auto refuse = [&](const std::string& m) { throw IoError(path + ": cannot write: " + m); };
  if (dim != 2 && dim != 3) refuse("dimension " + std::to_string(dim) + ", expected 2 or 3");
  if (n < 0) refuse("negative vertex count " + std::to_string(n) + ", expected a count >= 0");
  if (fields.empty()) refuse("no field, expected at least one");
  if (fields.size() > static_cast<std::size_t>(kMaxFields)) refuse("too many fields, expected at most 1000");
  std::vector<int> types;
  for (const auto& f : fields) {
    const int type = static_cast<int>(f.info.kind);
    const int expected = type_components(type, dim);
    const char* kind = type == 1 ? "scalar" : type == 2 ? "vector" : "tensor";
    if (expected == 0) refuse("field '" + f.info.name + "' has an unknown kind");
    if (f.info.ncomp != expected)
      refuse("field '" + f.info.name + "': " + kind + " with " + std::to_string(f.info.ncomp) + " components, expected " +
             std::to_string(expected) + " in dimension " + std::to_string(dim));
    const std::size_t want = static_cast<std::size_t>(n) * static_cast<std::size_t>(expected);
    if (f.size != want || (want > 0 && f.values == nullptr))
      refuse("field '" + f.info.name + "' has " + std::to_string(f.size) + " values, expected " +
             std::to_string(n) + " x " + std::to_string(expected) + " = " + std::to_string(want));
    for (std::size_t i = 0; i < f.size; ++i)
      if (!std::isfinite(f.values[i]))
        refuse("field '" + f.info.name + "': vertex " + std::to_string(i / static_cast<std::size_t>(expected) + 1) +
               " has a non-finite value");
    types.push_back(type);
  }
  return types;
}

// The names comment, or "" when every name is the default one or a name
// cannot be written as one token.
std::string names_comment(const std::vector<FieldView>& fields) {
  bool custom = false;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const std::string& name = fields[k].info.name;
    if (name.empty()) return "";
    for (char c : name)
      if (std::isspace(static_cast<unsigned char>(c)) || c == '#') return "";
    if (name != default_name(k)) custom = true;
  }
  if (!custom) return "";
  std::string s = "# " + std::string(kNamesTag);
  for (const auto& f : fields) s += " " + f.info.name;
  return s + "\n\n";
}

template <class T>
void put(std::string& buf, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  buf.append(b, sizeof(T));
}

}  // namespace

std::vector<FieldData> read_sol_ascii(const std::string& path, int n_vertices, int* dimension) {
  AsciiSolReader reader(read_file_contents(path), path, n_vertices);
  return reader.run(dimension);
}

std::vector<FieldData> read_sol_binary(const std::string& path, int n_vertices, int* dimension) {
  BinarySolReader reader(path, n_vertices);
  return reader.run(dimension);
}

void write_sol_ascii(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension) {
  const std::vector<int> types = check_fields(path, fields, n_vertices, dimension);
  AtomicFile f(path);
  std::string buf;
  buf.reserve(1 << 20);
  buf += "MeshVersionFormatted 2\n\nDimension " + std::to_string(dimension) + "\n\n";
  buf += names_comment(fields);
  buf += "SolAtVertices\n" + std::to_string(n_vertices) + "\n" + std::to_string(types.size());
  for (int t : types) {
    buf.push_back(' ');
    buf += std::to_string(t);
  }
  buf += "\n\n";
  for (int i = 0; i < n_vertices; ++i) {
    bool first = true;
    for (const auto& fd : fields) {
      const int nc = fd.info.ncomp;
      for (int c = 0; c < nc; ++c) {
        if (!first) buf.push_back(' ');
        first = false;
        append_double(buf, fd.values[static_cast<std::size_t>(i) * static_cast<std::size_t>(nc) + static_cast<std::size_t>(c)]);
      }
    }
    buf.push_back('\n');
    if (buf.size() > (1 << 20)) {
      f.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  buf += "\nEnd\n";
  f.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
  f.commit();
}

void write_sol_binary(const std::string& path, const std::vector<FieldView>& fields, int n_vertices, int dimension) {
  const std::vector<int> types = check_fields(path, fields, n_vertices, dimension);
  std::size_t comps = 0;
  for (const auto& fd : fields) comps += static_cast<std::size_t>(fd.info.ncomp);
  const std::size_t bound = 64 + 4 * types.size() + static_cast<std::size_t>(n_vertices) * comps * 8;
  const bool wide = bound >= static_cast<std::size_t>(INT_MAX);  // version 3: 64-bit positions
  const int version = wide ? 3 : 2;
  std::string buf;
  buf.reserve(bound);
  auto pos_slot = [&]() {
    const std::size_t slot = buf.size();
    if (wide)
      put(buf, std::int64_t{0});
    else
      put(buf, std::int32_t{0});
    return slot;
  };
  auto patch = [&](std::size_t slot) {
    if (wide) {
      const auto p = static_cast<std::int64_t>(buf.size());
      std::memcpy(&buf[slot], &p, sizeof p);
    } else {
      const auto p = static_cast<std::int32_t>(buf.size());
      std::memcpy(&buf[slot], &p, sizeof p);
    }
  };
  put(buf, std::int32_t{1});
  put(buf, std::int32_t{version});
  put(buf, std::int32_t{kGmfDimension});
  std::size_t slot = pos_slot();
  put(buf, std::int32_t{dimension});
  patch(slot);
  put(buf, std::int32_t{kGmfSolAtVertices});
  slot = pos_slot();
  put(buf, std::int32_t{n_vertices});
  put(buf, static_cast<std::int32_t>(types.size()));
  for (int t : types) put(buf, std::int32_t{t});
  for (int i = 0; i < n_vertices; ++i)
    for (const auto& fd : fields) {
      const auto nc = static_cast<std::size_t>(fd.info.ncomp);
      for (std::size_t c = 0; c < nc; ++c) put(buf, fd.values[static_cast<std::size_t>(i) * nc + c]);
    }
  patch(slot);
  put(buf, std::int32_t{kGmfEnd});
  pos_slot();  // the last keyword keeps next position 0
  AtomicFile f(path);
  f.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
  f.commit();
}

}  // namespace anisurf::io
