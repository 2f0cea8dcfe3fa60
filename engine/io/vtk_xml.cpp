// VTK XML files: UnstructuredGrid (.vtu) and PolyData (.vtp).
// Reading: every Piece; data arrays in format "ascii", "binary" (inline
// base64) or "appended" (AppendedData encoding "raw" or "base64"), header
// UInt32 or UInt64, either byte order, uncompressed or vtkZLibDataCompressor.
// Cells: .vtu triangles (type 5, or a polygon of type 7 with 3 vertices) and
// lines (type 3, as edges); .vtp Polys of 3 vertices and Lines (each segment
// of a polyline an edge); other cells are skipped with a warning. Cell data:
// the first integer array named "medit:ref", "ref", "gmsh:physical" or
// "CellEntityIds" gives the triangle and edge refs; other cell arrays are
// skipped. Point data: an integer array "vertex_ref" or "medit:ref" of one
// component gives the vertex refs; other arrays become fields: 1 component
// scalar, 3 vector, 6 symmetric tensor (VTK order XX YY ZZ XY YZ XZ), 9 3x3
// tensor (made symmetric with a warning if it is not), 2, 4 or 5 a scalar
// field of that many components; others are skipped with a warning.
// Writing: Points Float64; .vtu cells triangles then edges (connectivity and
// offsets Int64, types UInt8); .vtp Lines and Polys; cell data "medit:ref"
// (Int32) when the mesh has refs; point data "vertex_ref" (Int32) and the
// fields (Float64; vectors of 3, tensors as 9 components). Header UInt64.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/field_layout.h"
#include "io/formats.h"
#include "io/text_reader.h"
#include "io/vtk_xml_encoding.h"

namespace anisurf::io {
namespace {

constexpr int kMaxDepth = 32;
constexpr std::size_t kZlibMaxRatio = 1100;  // zlib inflates at most ~1032:1

// ------------------------------------------------------------- XML parsing

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<int> children;
  std::string_view text;  // content between the tags (leaf elements)
  std::size_t offset = 0;  // of the '<'
  const std::string* attribute(std::string_view key) const {
    for (const auto& a : attributes)
      if (a.first == key) return &a.second;
    return nullptr;
  }
};

class XmlDocument {
 public:
  XmlDocument(const std::string& data, std::size_t end, const std::string& path) : d_(data), end_(end), path_(path) {}
  void parse();
  const XmlElement& element(int i) const { return elements_[static_cast<std::size_t>(i)]; }
  const XmlElement& root() const { return elements_.front(); }
  // The first child of `parent` named `name`, or -1.
  int child(const XmlElement& parent, std::string_view name) const;
  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const;

 private:
  std::size_t skip_misc(std::size_t p) const;
  std::size_t parse_tag(std::size_t p, XmlElement& e, bool& self_closing) const;
  std::string decode_entities(std::string_view s, std::size_t offset) const;
  const std::string& d_;
  std::size_t end_;
  const std::string& path_;
  std::vector<XmlElement> elements_;
};

void XmlDocument::fail_at(std::size_t offset, const std::string& message) const {
  offset = std::min(offset, d_.size());
  const auto line = 1 + std::count(d_.begin(), d_.begin() + static_cast<std::ptrdiff_t>(offset), '\n');
  throw IoError(path_ + ":" + std::to_string(line) + ": " + message);
}

int XmlDocument::child(const XmlElement& parent, std::string_view name) const {
  for (int c : parent.children)
    if (element(c).name == name) return c;
  return -1;
}

// Skips whitespace, comments, <?...?> and <!...> declarations.
std::size_t XmlDocument::skip_misc(std::size_t p) const {
  for (;;) {
    while (p < end_ && std::isspace(static_cast<unsigned char>(d_[p]))) ++p;
    if (d_.compare(p, 4, "<!--") == 0) {
      const std::size_t q = d_.find("-->", p + 4);
      if (q == std::string::npos || q >= end_) fail_at(p, "comment without '-->'");
      p = q + 3;
    } else if (d_.compare(p, 2, "<?") == 0 || d_.compare(p, 2, "<!") == 0) {
      const std::size_t q = d_.find('>', p);
      if (q == std::string::npos || q >= end_) fail_at(p, "declaration without '>'");
      p = q + 1;
    } else {
      return p;
    }
  }
}

std::string XmlDocument::decode_entities(std::string_view s, std::size_t offset) const {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '&') {
      out += s[i];
      continue;
    }
    const std::size_t semi = s.find(';', i);
    const std::string_view ent = semi == std::string_view::npos ? s.substr(i) : s.substr(i, semi - i + 1);
    if (ent == "&amp;") out += '&';
    else if (ent == "&lt;") out += '<';
    else if (ent == "&gt;") out += '>';
    else if (ent == "&quot;") out += '"';
    else if (ent == "&apos;") out += '\'';
    else fail_at(offset, "unknown entity " + quoted(ent) + ", expected &amp; &lt; &gt; &quot; or &apos;");
    i += ent.size() - 1;
  }
  return out;
}

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
}

// Parses "<name attr="v" ...>" or "<name .../>" at p; returns the offset past it.
std::size_t XmlDocument::parse_tag(std::size_t p, XmlElement& e, bool& self_closing) const {
  e.offset = p;
  std::size_t q = p + 1;
  while (q < end_ && is_name_char(d_[q])) ++q;
  if (q == p + 1) fail_at(p, "expected an element name after '<'");
  e.name = d_.substr(p + 1, q - p - 1);
  for (;;) {
    while (q < end_ && std::isspace(static_cast<unsigned char>(d_[q]))) ++q;
    if (q >= end_) fail_at(p, "element <" + e.name + "> without '>'");
    if (d_[q] == '>') {
      self_closing = false;
      return q + 1;
    }
    if (d_.compare(q, 2, "/>") == 0) {
      self_closing = true;
      return q + 2;
    }
    const std::size_t a = q;
    while (q < end_ && is_name_char(d_[q])) ++q;
    if (q == a) fail_at(q, "expected an attribute name or '>' in <" + e.name + ">, found " + quoted(d_.substr(q, 1)));
    std::string key = d_.substr(a, q - a);
    while (q < end_ && std::isspace(static_cast<unsigned char>(d_[q]))) ++q;
    if (q >= end_ || d_[q] != '=') fail_at(q, "expected '=' after attribute " + key);
    ++q;
    while (q < end_ && std::isspace(static_cast<unsigned char>(d_[q]))) ++q;
    if (q >= end_ || (d_[q] != '"' && d_[q] != '\'')) fail_at(q, "expected a quoted value of attribute " + key);
    const char quote = d_[q];
    const std::size_t close = d_.find(quote, q + 1);
    if (close == std::string::npos || close >= end_) fail_at(q, "attribute " + key + " without its closing quote");
    e.attributes.push_back({std::move(key), decode_entities(std::string_view(d_).substr(q + 1, close - q - 1), q)});
    q = close + 1;
  }
}

void XmlDocument::parse() {
  std::size_t p = skip_misc(0);
  if (p >= end_ || d_[p] != '<') fail_at(p, "expected an XML element '<VTKFile ...>'");
  std::vector<int> open;  // stack of open elements
  std::size_t text_start = 0;
  for (;;) {
    if (open.empty() && !elements_.empty()) {
      if (skip_misc(p) < end_) fail_at(p, "content after the root element, expected the end of the file");
      return;
    }
    if (!open.empty()) {
      const std::size_t lt = d_.find('<', p);
      // Before <AppendedData> (end_ < the file size) the root is still open.
      if ((lt == std::string::npos || lt >= end_) && open.size() == 1 && end_ < d_.size()) return;
      if (lt == std::string::npos || lt >= end_)
        fail_at(p, "unexpected end of file, expected </" + element(open.back()).name + ">");
      p = lt;
    } else if (p >= end_ || d_[p] != '<') {
      fail_at(p, "expected an XML element '<VTKFile ...>'");
    }
    if (d_.compare(p, 4, "<!--") == 0 || d_.compare(p, 2, "<?") == 0) {
      p = skip_misc(p);
      continue;
    }
    if (d_.compare(p, 2, "</") == 0) {
      if (open.empty()) fail_at(p, "closing tag before any element, expected '<VTKFile ...>'");
      const std::size_t gt = d_.find('>', p);
      if (gt == std::string::npos || gt >= end_) fail_at(p, "closing tag without '>'");
      std::string name = d_.substr(p + 2, gt - p - 2);
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      XmlElement& top = elements_[static_cast<std::size_t>(open.back())];
      if (name != top.name) fail_at(p, "expected </" + top.name + ">, found </" + name.substr(0, 40) + ">");
      if (top.children.empty()) top.text = std::string_view(d_).substr(text_start, p - text_start);
      open.pop_back();
      p = gt + 1;
      continue;
    }
    if (open.size() >= kMaxDepth) fail_at(p, "elements nested deeper than " + std::to_string(kMaxDepth));
    XmlElement e;
    bool self_closing = false;
    p = parse_tag(p, e, self_closing);
    const int id = static_cast<int>(elements_.size());
    if (!open.empty()) elements_[static_cast<std::size_t>(open.back())].children.push_back(id);
    elements_.push_back(std::move(e));
    if (!self_closing) {
      open.push_back(id);
      text_start = p;
    }
  }
}

// ---------------------------------------------------------- data arrays

enum class ValueType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

bool parse_value_type(std::string_view s, ValueType& t) {
  static const std::pair<const char*, ValueType> names[] = {
      {"Int8", ValueType::Int8},       {"UInt8", ValueType::UInt8},     {"Int16", ValueType::Int16},
      {"UInt16", ValueType::UInt16},   {"Int32", ValueType::Int32},     {"UInt32", ValueType::UInt32},
      {"Int64", ValueType::Int64},     {"UInt64", ValueType::UInt64},   {"Float32", ValueType::Float32},
      {"Float64", ValueType::Float64}, {"Char", ValueType::Int8},       {"UChar", ValueType::UInt8}};
  for (const auto& [n, v] : names)
    if (s == n) {
      t = v;
      return true;
    }
  return false;
}

std::size_t value_size(ValueType t) {
  switch (t) {
    case ValueType::Int8:
    case ValueType::UInt8: return 1;
    case ValueType::Int16:
    case ValueType::UInt16: return 2;
    case ValueType::Int32:
    case ValueType::UInt32:
    case ValueType::Float32: return 4;
    default: return 8;
  }
}

bool is_integer(ValueType t) { return t != ValueType::Float32 && t != ValueType::Float64; }

template <class T>
double load(const char* p, bool swap) {
  char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = swap ? p[sizeof(T) - 1 - i] : p[i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return static_cast<double>(v);
}

double load_value(const char* p, ValueType t, bool swap) {
  switch (t) {
    case ValueType::Int8: return load<std::int8_t>(p, swap);
    case ValueType::UInt8: return load<std::uint8_t>(p, swap);
    case ValueType::Int16: return load<std::int16_t>(p, swap);
    case ValueType::UInt16: return load<std::uint16_t>(p, swap);
    case ValueType::Int32: return load<std::int32_t>(p, swap);
    case ValueType::UInt32: return load<std::uint32_t>(p, swap);
    case ValueType::Int64: return load<std::int64_t>(p, swap);
    case ValueType::UInt64: return load<std::uint64_t>(p, swap);
    case ValueType::Float32: return load<float>(p, swap);
    case ValueType::Float64: return load<double>(p, swap);
  }
  return 0;
}

struct DataArray {
  std::string name;
  ValueType type = ValueType::Float64;
  int ncomp = 1;
  std::vector<double> values;
};

class VtkXmlReader {
 public:
  explicit VtkXmlReader(const std::string& path) : path_(path), data_(read_file_contents(path)) {}
  MeshData read();

 private:
  void locate_appended();
  void read_header();
  void read_piece(const XmlElement& piece, MeshData& d);
  // The array's values (tuples x components of them, checked).
  DataArray read_array(const XmlElement& e, long long tuples, int ncomp_expected);
  std::string array_bytes(const XmlElement& e, std::size_t expected_bytes);
  std::string decode_block(std::string_view header_and_data_source, const XmlElement& e, std::size_t expected_bytes,
                           bool base64, std::size_t appended_offset);
  std::uint64_t header_uint(const std::string& bytes, std::size_t index) const;
  long long count_attribute(const XmlElement& e, const char* key, bool required) const;
  // The connectivity size: the last end offset (0 without cells), checked.
  long long connectivity_size(const XmlElement& e, const DataArray& offsets) const;
  // A reference of an integer array: an int, or a failure naming the array.
  int ref_value(const XmlElement& e, double v) const;
  // Fails unless the cell end offsets increase up to n_conn.
  void check_offsets(const XmlElement& e, const DataArray& offsets, long long n_conn, const std::string& what) const;
  void read_cells_vtu(const XmlElement& piece, long long n_points, long long n_cells, MeshData& d,
                      std::vector<std::pair<int, int>>& cell_items, long long base);
  void read_cells_vtp(const XmlElement& piece, long long n_points, MeshData& d,
                      std::vector<std::pair<int, int>>& cell_items, long long base);
  void read_point_data(const XmlElement& piece, long long n_points, MeshData& d, std::size_t base);
  void read_cell_data(const XmlElement& piece, long long n_cells, MeshData& d,
                      const std::vector<std::pair<int, int>>& cell_items, std::size_t tri_base, std::size_t edge_base);
  [[noreturn]] void fail(const XmlElement& e, const std::string& m) const { xml_->fail_at(e.offset, m); }
  [[noreturn]] void fail_byte(std::size_t offset, const std::string& m) const {
    throw IoError(path_ + ": byte " + std::to_string(offset) + ": " + m);
  }

  std::string path_;
  std::string data_;
  std::unique_ptr<XmlDocument> xml_;
  std::size_t xml_end_ = 0;
  std::size_t appended_ = std::string::npos;  // first byte after the '_'
  bool appended_base64_ = false;
  bool swap_ = false;
  int header_bytes_ = 4;
  bool compressed_ = false;
  bool poly_ = false;
  // Kind of each cell: (1 triangle / 2 edges / 0 skipped, count of edges or triangles).
  std::map<std::string, long long> skipped_cells_;
  std::vector<std::string> skipped_arrays_;
};

void VtkXmlReader::locate_appended() {
  xml_end_ = data_.size();
  const std::size_t at = data_.find("<AppendedData");
  if (at == std::string::npos) return;
  const std::size_t gt = data_.find('>', at);
  if (gt == std::string::npos) throw IoError(path_ + ": byte " + std::to_string(at) + ": <AppendedData without '>'");
  const std::string tag = data_.substr(at, gt - at);
  if (tag.find("encoding=\"base64\"") != std::string::npos || tag.find("encoding='base64'") != std::string::npos)
    appended_base64_ = true;
  else if (tag.find("encoding=\"raw\"") == std::string::npos && tag.find("encoding='raw'") == std::string::npos)
    throw IoError(path_ + ": byte " + std::to_string(at) + ": AppendedData encoding, expected \"raw\" or \"base64\"");
  const std::size_t underscore = data_.find('_', gt);
  if (underscore == std::string::npos)
    throw IoError(path_ + ": byte " + std::to_string(gt) + ": expected '_' starting the appended data");
  appended_ = underscore + 1;
  xml_end_ = at;
}

std::uint64_t VtkXmlReader::header_uint(const std::string& bytes, std::size_t index) const {
  const char* p = bytes.data() + index * static_cast<std::size_t>(header_bytes_);
  std::uint64_t v = 0;
  for (int i = 0; i < header_bytes_; ++i) {
    const auto byte = static_cast<unsigned char>(p[swap_ == host_is_little_endian() ? i : header_bytes_ - 1 - i]);
    v = (v << 8) | byte;
  }
  return v;
}

long long VtkXmlReader::count_attribute(const XmlElement& e, const char* key, bool required) const {
  const std::string* s = e.attribute(key);
  if (!s) {
    if (required) fail(e, std::string("<") + e.name + "> without " + key + ", expected " + key + "=\"N\"");
    return 0;
  }
  long long v = 0;
  if (!parse_integer(*s, v) || v < 0)
    fail(e, std::string(key) + "=" + quoted(*s) + ", expected a count >= 0");
  // Every point or cell takes at least a byte of the file.
  if (static_cast<unsigned long long>(v) > data_.size() * kZlibMaxRatio)
    fail(e, std::string(key) + " " + std::to_string(v) + " impossible for a file of " + std::to_string(data_.size()) +
                " bytes, expected a count that fits the file");
  return v;
}

// Bytes of a binary array: header + data from inline base64 or appended data
// (raw or base64), inflated when compressed. Exactly expected_bytes long.
std::string VtkXmlReader::decode_block(std::string_view source, const XmlElement& e, std::size_t expected_bytes,
                                       bool base64, std::size_t where) {
  // `source` starts at the array's first byte (raw) or character (base64).
  std::string bytes;
  Base64Decoder decoder(source);
  auto take = [&](std::size_t n) -> bool {  // makes bytes hold n bytes
    if (bytes.size() >= n) return true;
    if (base64) return decoder.decode_until(n, bytes);
    const std::size_t need = n - bytes.size();
    if (need > source.size() - bytes.size()) return false;
    bytes.append(source.substr(bytes.size(), need));
    return true;
  };
  const std::string* name_attr = e.attribute("Name");
  const std::string name = "data array '" + (name_attr ? *name_attr : std::string()) + "'";
  auto truncated = [&](const std::string& what) -> void {
    if (where == std::string::npos) fail(e, name + ": truncated or invalid base64, expected " + what);
    fail_byte(where, name + ": truncated appended data, expected " + what);
  };
  const std::size_t hb = static_cast<std::size_t>(header_bytes_);
  if (!compressed_) {
    if (!take(hb)) truncated("the array's size header");
    const std::uint64_t n = header_uint(bytes, 0);
    if (n != expected_bytes)
      fail(e, name + " of " + std::to_string(n) + " bytes, expected " + std::to_string(expected_bytes));
    if (!take(hb + expected_bytes)) truncated(std::to_string(expected_bytes) + " bytes of data");
    return bytes.substr(hb, expected_bytes);
  }
  if (!take(3 * hb)) truncated("the compression header");
  const std::uint64_t n_blocks = header_uint(bytes, 0), block = header_uint(bytes, 1), last = header_uint(bytes, 2);
  const std::uint64_t last_size = last == 0 ? block : last;
  const std::uint64_t total = n_blocks == 0 ? 0 : (n_blocks - 1) * block + last_size;
  if (block == 0 || block > (1ULL << 40) || n_blocks > expected_bytes + 1 || total != expected_bytes)
    fail(e, name + ": compression header gives " + std::to_string(n_blocks) + " blocks of " + std::to_string(block) +
                " bytes (last " + std::to_string(last) + "), expected " + std::to_string(expected_bytes) + " bytes");
  if (!take((3 + n_blocks) * hb)) truncated("the compressed block sizes");
  std::uint64_t compressed = 0;
  for (std::uint64_t b = 0; b < n_blocks; ++b) compressed += header_uint(bytes, 3 + b);
  if (expected_bytes > compressed * kZlibMaxRatio + 1024)
    fail(e, std::to_string(compressed) + " compressed bytes cannot hold " + std::to_string(expected_bytes) +
                ", expected a consistent compression header");
  const std::size_t head = (3 + n_blocks) * hb;
  if (compressed > data_.size() || !take(head + compressed)) truncated(std::to_string(compressed) + " compressed bytes");
  std::string out;
  out.reserve(expected_bytes);
  std::size_t at = head;
  for (std::uint64_t b = 0; b < n_blocks; ++b) {
    const std::uint64_t c = header_uint(bytes, 3 + b);
    const std::uint64_t size = b + 1 == n_blocks ? last_size : block;
    if (!zlib_inflate_block(std::string_view(bytes).substr(at, c), size, out))
      fail(e, name + ": zlib block " + std::to_string(b) + " is corrupt, expected " + std::to_string(size) + " bytes from it");
    at += c;
  }
  return out;
}

std::string VtkXmlReader::array_bytes(const XmlElement& e, std::size_t expected_bytes) {
  const std::string* format = e.attribute("format");
  if (format && *format == "binary") return decode_block(e.text, e, expected_bytes, true, std::string::npos);
  // appended
  const std::string* off = e.attribute("offset");
  long long offset = -1;
  if (!off || !parse_integer(*off, offset) || offset < 0) fail(e, "appended data array without a valid offset");
  if (appended_ == std::string::npos) fail(e, "appended data array but no <AppendedData>, expected one");
  if (static_cast<unsigned long long>(offset) > data_.size() - appended_)
    fail(e, "offset " + std::to_string(offset) + " past the end of the appended data");
  const std::size_t start = appended_ + static_cast<std::size_t>(offset);
  return decode_block(std::string_view(data_).substr(start), e, expected_bytes, appended_base64_, start);
}

DataArray VtkXmlReader::read_array(const XmlElement& e, long long tuples, int ncomp_expected) {
  DataArray a;
  if (const std::string* n = e.attribute("Name")) a.name = *n;
  const std::string* type = e.attribute("type");
  if (!type || !parse_value_type(*type, a.type))
    fail(e, "data array '" + a.name + "': type " + (type ? quoted(*type) : std::string("missing")) +
                ", expected Int8 .. UInt64, Float32 or Float64");
  a.ncomp = 1;
  if (const std::string* nc = e.attribute("NumberOfComponents")) {
    long long v = 0;
    if (!parse_integer(*nc, v) || v < 1 || v > 64)
      fail(e, "data array '" + a.name + "': NumberOfComponents " + quoted(*nc) + ", expected 1..64");
    a.ncomp = static_cast<int>(v);
  }
  if (ncomp_expected > 0 && a.ncomp != ncomp_expected)
    fail(e, "data array '" + a.name + "' has " + std::to_string(a.ncomp) + " components, expected " +
                std::to_string(ncomp_expected));
  const unsigned long long count = static_cast<unsigned long long>(tuples) * static_cast<unsigned long long>(a.ncomp);
  const std::string* format = e.attribute("format");
  if (!format || (*format != "ascii" && *format != "binary" && *format != "appended"))
    fail(e, "data array '" + a.name + "': format " + (format ? quoted(*format) : std::string("missing")) +
                ", expected ascii, binary or appended");
  if (*format == "ascii") {
    if (count > e.text.size() / 2 + 1)
      fail(e, "data array '" + a.name + "' holds fewer than the " + std::to_string(count) + " values expected");
    TextReader r(std::string(e.text), path_, '\0');
    a.values.reserve(count);
    for (unsigned long long i = 0; i < count; ++i) {
      std::string_view t;
      if (!r.next(t)) fail(e, "data array '" + a.name + "' has " + std::to_string(i) + " values, expected " +
                                  std::to_string(count));
      double v = 0;
      if (!parse_real(t, v)) fail(e, "data array '" + a.name + "': expected a number, found " + quoted(t));
      a.values.push_back(v);
    }
    if (!r.at_end()) fail(e, "data array '" + a.name + "' has more than the " + std::to_string(count) + " values expected");
  } else {
    const std::size_t size = value_size(a.type);
    if (count > data_.size() * kZlibMaxRatio / size)
      fail(e, "data array '" + a.name + "' of " + std::to_string(count) + " values cannot fit the file");
    const std::string bytes = array_bytes(e, static_cast<std::size_t>(count) * size);
    a.values.resize(count);
    for (std::size_t i = 0; i < count; ++i) a.values[i] = load_value(bytes.data() + i * size, a.type, swap_);
  }
  if (!is_integer(a.type))
    for (std::size_t i = 0; i < a.values.size(); ++i)
      if (!std::isfinite(a.values[i]))
        fail(e, "data array '" + a.name + "': value " + std::to_string(i) + " is not a finite number");
  return a;
}

void VtkXmlReader::read_header() {
  const XmlElement& root = xml_->root();
  if (root.name != "VTKFile") fail(root, "root element <" + root.name + ">, expected <VTKFile>");
  const std::string* type = root.attribute("type");
  if (!type || (*type != "UnstructuredGrid" && *type != "PolyData"))
    fail(root, "VTKFile type " + (type ? quoted(*type) : std::string("missing")) +
                   ", expected UnstructuredGrid (.vtu) or PolyData (.vtp)");
  poly_ = *type == "PolyData";
  const std::string* order = root.attribute("byte_order");
  if (order && *order != "LittleEndian" && *order != "BigEndian")
    fail(root, "byte_order " + quoted(*order) + ", expected LittleEndian or BigEndian");
  swap_ = (order && *order == "BigEndian") == host_is_little_endian();
  if (const std::string* h = root.attribute("header_type")) {
    if (*h != "UInt32" && *h != "UInt64") fail(root, "header_type " + quoted(*h) + ", expected UInt32 or UInt64");
    header_bytes_ = *h == "UInt32" ? 4 : 8;
  }
  if (const std::string* c = root.attribute("compressor")) {
    if (*c != "vtkZLibDataCompressor" && !c->empty())
      fail(root, "compressor " + quoted(*c) + " unsupported, expected vtkZLibDataCompressor or none");
    compressed_ = !c->empty();
  }
}

long long VtkXmlReader::connectivity_size(const XmlElement& e, const DataArray& offsets) const {
  const double last = offsets.values.empty() ? 0.0 : offsets.values.back();
  if (!(last >= 0 && last <= static_cast<double>(data_.size()) * kZlibMaxRatio))
    fail(e, "last offset " + format_double(last) + " impossible, expected the connectivity size");
  return static_cast<long long>(last);
}

int VtkXmlReader::ref_value(const XmlElement& e, double v) const {
  int r = 0;
  if (!int_from_double(v, r)) fail(e, "reference " + format_double(v) + ", expected an integer of the int range");
  return r;
}

void VtkXmlReader::check_offsets(const XmlElement& e, const DataArray& offsets, long long n_conn,
                                 const std::string& what) const {
  double prev = 0;
  for (std::size_t i = 0; i < offsets.values.size(); ++i) {
    const double end = offsets.values[i];
    if (!(end >= prev && end <= static_cast<double>(n_conn)))
      fail(e, what + "offset " + std::to_string(static_cast<long long>(end)) + " of cell " + std::to_string(i) +
                  " out of order, expected " + std::to_string(static_cast<long long>(prev)) + ".." +
                  std::to_string(n_conn));
    prev = end;
  }
}

void add_skipped(std::map<std::string, long long>& skipped, const std::string& what) { ++skipped[what]; }

void VtkXmlReader::read_cells_vtu(const XmlElement& piece, long long n_points, long long n_cells, MeshData& d,
                                  std::vector<std::pair<int, int>>& cell_items, long long base) {
  const int cells = xml_->child(piece, "Cells");
  if (cells < 0) {
    if (n_cells > 0) fail(piece, "piece without <Cells>, expected connectivity, offsets and types");
    return;
  }
  const XmlElement& c = xml_->element(cells);
  const XmlElement* conn = nullptr;
  const XmlElement* offs = nullptr;
  const XmlElement* types = nullptr;
  for (int k : c.children) {
    const XmlElement& a = xml_->element(k);
    const std::string* name = a.attribute("Name");
    if (!name) continue;
    if (*name == "connectivity") conn = &a;
    if (*name == "offsets") offs = &a;
    if (*name == "types") types = &a;
  }
  if (!conn || !offs || !types) fail(c, "<Cells> without connectivity, offsets and types arrays");
  const DataArray o = read_array(*offs, n_cells, 1);
  const DataArray t = read_array(*types, n_cells, 1);
  const long long n_conn = connectivity_size(*offs, o);
  check_offsets(*offs, o, n_conn, "");
  const DataArray conn_a = read_array(*conn, n_conn, 1);
  long long prev = 0;
  for (long long i = 0; i < n_cells; ++i) {
    const auto end = static_cast<long long>(o.values[static_cast<std::size_t>(i)]);
    const long long size = end - prev;
    std::vector<int> ids;
    for (long long k = prev; k < end; ++k) {
      const double v = conn_a.values[static_cast<std::size_t>(k)];
      if (!(v >= 0 && v < static_cast<double>(n_points)))
        fail(*conn, "cell " + std::to_string(i) + ": point id " + format_double(v) +
                        " out of range, expected 0.." + std::to_string(n_points - 1));
      ids.push_back(static_cast<int>(v + static_cast<double>(base)));
    }
    int type = -1;
    if (!int_from_double(t.values[static_cast<std::size_t>(i)], type)) type = -1;
    if ((type == 5 || type == 7) && size == 3) {
      cell_items.push_back({1, 1});
      d.triangles.push_back({ids[0], ids[1], ids[2]});
    } else if (type == 3 && size == 2) {
      cell_items.push_back({2, 1});
      d.edges.push_back({ids[0], ids[1]});
    } else {
      cell_items.push_back({0, 0});
      add_skipped(skipped_cells_, "cells of VTK type " + std::to_string(type));
    }
    prev = end;
  }
}

void VtkXmlReader::read_cells_vtp(const XmlElement& piece, long long n_points, MeshData& d,
                                  std::vector<std::pair<int, int>>& cell_items, long long base) {
  for (const char* section : {"Verts", "Lines", "Strips", "Polys"}) {
    const long long n = count_attribute(piece, (std::string("NumberOf") + section).c_str(), false);
    const int s = xml_->child(piece, section);
    if (s < 0) {
      if (n > 0) fail(piece, std::string("piece announces ") + std::to_string(n) + " " + section + " but has no <" +
                                 section + ">");
      continue;
    }
    const XmlElement& sec = xml_->element(s);
    const XmlElement* conn = nullptr;
    const XmlElement* offs = nullptr;
    for (int k : sec.children) {
      const XmlElement& a = xml_->element(k);
      if (const std::string* name = a.attribute("Name")) {
        if (*name == "connectivity") conn = &a;
        if (*name == "offsets") offs = &a;
      }
    }
    if (!conn || !offs) fail(sec, std::string("<") + section + "> without connectivity and offsets arrays");
    const DataArray o = read_array(*offs, n, 1);
    const long long n_conn = connectivity_size(*offs, o);
    const std::string what = section;
    check_offsets(*offs, o, n_conn, what + " ");
    const DataArray c = read_array(*conn, n_conn, 1);
    long long prev = 0;
    for (long long i = 0; i < n; ++i) {
      const auto end = static_cast<long long>(o.values[static_cast<std::size_t>(i)]);
      std::vector<int> ids;
      for (long long k = prev; k < end; ++k) {
        const double v = c.values[static_cast<std::size_t>(k)];
        if (!(v >= 0 && v < static_cast<double>(n_points)))
          fail(*conn, what + " cell " + std::to_string(i) + ": point id " + format_double(v) +
                          " out of range, expected 0.." + std::to_string(n_points - 1));
        ids.push_back(static_cast<int>(v + static_cast<double>(base)));
      }
      if (what == "Polys" && ids.size() == 3) {
        cell_items.push_back({1, 1});
        d.triangles.push_back({ids[0], ids[1], ids[2]});
      } else if (what == "Lines" && ids.size() >= 2) {
        cell_items.push_back({2, static_cast<int>(ids.size() - 1)});
        for (std::size_t k = 0; k + 1 < ids.size(); ++k) d.edges.push_back({ids[k], ids[k + 1]});
      } else {
        cell_items.push_back({0, 0});
        add_skipped(skipped_cells_, what == "Polys" ? "polygons of " + std::to_string(ids.size()) + " vertices"
                                                    : what + " cells");
      }
      prev = end;
    }
  }
}

bool is_ref_name(const std::string& n) {
  return n == "medit:ref" || n == "ref" || n == "gmsh:physical" || n == "CellEntityIds";
}

void VtkXmlReader::read_point_data(const XmlElement& piece, long long n_points, MeshData& d, std::size_t base) {
  const int pd = xml_->child(piece, "PointData");
  if (pd < 0) return;
  int unnamed = 0;
  for (int k : xml_->element(pd).children) {
    const XmlElement& e = xml_->element(k);
    if (e.name != "DataArray") continue;
    DataArray a = read_array(e, n_points, 0);
    if (a.name.empty()) a.name = "field" + std::to_string(unnamed++);
    if ((a.name == "vertex_ref" || a.name == "medit:ref") && a.ncomp == 1 && is_integer(a.type)) {
      d.vertex_refs.resize(base + static_cast<std::size_t>(n_points), 0);
      for (long long i = 0; i < n_points; ++i)
        d.vertex_refs[base + static_cast<std::size_t>(i)] = ref_value(e, a.values[static_cast<std::size_t>(i)]);
      continue;
    }
    FieldData f;
    long long asymmetric = 0;
    if (a.ncomp == 6) {
      f.info = {a.name, FieldKind::Tensor, 6};
      f.values.resize(a.values.size());
      for (std::size_t i = 0; i < a.values.size(); i += 6) {
        const double* v = a.values.data() + i;  // XX YY ZZ XY YZ XZ
        const double sym[6] = {v[0], v[3], v[1], v[5], v[4], v[2]};
        std::copy(sym, sym + 6, f.values.begin() + static_cast<std::ptrdiff_t>(i));
      }
    } else if (a.ncomp == 2 || a.ncomp == 4 || a.ncomp == 5) {
      f.info = {a.name, FieldKind::Scalar, a.ncomp};
      f.values = std::move(a.values);
    } else if (!field_from_layout(a.name, a.ncomp, a.values, f, &asymmetric)) {
      skipped_arrays_.push_back("point array '" + a.name + "' of " + std::to_string(a.ncomp) + " components");
      continue;
    }
    if (asymmetric > 0) d.warnings.push_back(asymmetric_warning(path_, a.name, asymmetric));
    auto same = std::find_if(d.fields.begin(), d.fields.end(), [&](const FieldData& g) { return g.info.name == f.info.name; });
    if (same == d.fields.end()) {
      if (base > 0) {
        skipped_arrays_.push_back("point array '" + a.name + "' of a later piece only");
        continue;
      }
      d.fields.push_back(std::move(f));
    } else if (same->info.ncomp == f.info.ncomp && same->info.kind == f.info.kind && same->values.size() == base * static_cast<std::size_t>(f.info.ncomp)) {
      same->values.insert(same->values.end(), f.values.begin(), f.values.end());
    } else {
      fail(e, "point array '" + a.name + "' twice or with another size in another piece, expected one per piece");
    }
  }
}

void VtkXmlReader::read_cell_data(const XmlElement& piece, long long n_cells, MeshData& d,
                                  const std::vector<std::pair<int, int>>& cell_items, std::size_t tri_base,
                                  std::size_t edge_base) {
  const int cd = xml_->child(piece, "CellData");
  bool have_refs = false;
  if (cd >= 0)
    for (int k : xml_->element(cd).children) {
      const XmlElement& e = xml_->element(k);
      if (e.name != "DataArray") continue;
      const std::string* name = e.attribute("Name");
      const std::string n = name ? *name : std::string();
      ValueType type = ValueType::Float64;
      const std::string* tn = e.attribute("type");
      const bool integer = tn && parse_value_type(*tn, type) && is_integer(type);
      const std::string* nc = e.attribute("NumberOfComponents");
      if (have_refs || !is_ref_name(n) || !integer || (nc && *nc != "1")) {
        skipped_arrays_.push_back("cell array '" + n + "'");
        continue;
      }
      const DataArray a = read_array(e, n_cells, 1);
      have_refs = true;
      std::size_t t = tri_base, ed = edge_base;
      for (std::size_t i = 0; i < cell_items.size(); ++i) {
        const int ref = ref_value(e, a.values[i]);
        if (cell_items[i].first == 1) d.triangle_refs[t++] = ref;
        if (cell_items[i].first == 2)
          for (int j = 0; j < cell_items[i].second; ++j) d.edge_refs[ed++] = ref;
      }
    }
}

void VtkXmlReader::read_piece(const XmlElement& piece, MeshData& d) {
  const long long n_points = count_attribute(piece, "NumberOfPoints", true);
  const long long base = static_cast<long long>(d.vertices.size());
  const int pts = xml_->child(piece, "Points");
  if (pts < 0 && n_points > 0) fail(piece, "piece without <Points>, expected the point coordinates");
  if (pts >= 0) {
    const XmlElement& p = xml_->element(pts);
    const int arr = xml_->child(p, "DataArray");
    if (arr < 0) fail(p, "<Points> without a DataArray, expected 3 components per point");
    const DataArray a = read_array(xml_->element(arr), n_points, 3);
    for (long long i = 0; i < n_points; ++i)
      d.vertices.push_back({a.values[3 * i], a.values[3 * i + 1], a.values[3 * i + 2]});
  }
  const std::size_t tri_base = d.triangles.size(), edge_base = d.edges.size();
  std::vector<std::pair<int, int>> cell_items;
  long long n_cells = 0;
  if (poly_) {
    read_cells_vtp(piece, n_points, d, cell_items, base);
    n_cells = static_cast<long long>(cell_items.size());
  } else {
    n_cells = count_attribute(piece, "NumberOfCells", true);
    read_cells_vtu(piece, n_points, n_cells, d, cell_items, base);
  }
  d.triangle_refs.resize(d.triangles.size(), 0);
  d.edge_refs.resize(d.edges.size(), 0);
  read_point_data(piece, n_points, d, static_cast<std::size_t>(base));
  read_cell_data(piece, n_cells, d, cell_items, tri_base, edge_base);
  if (!d.vertex_refs.empty()) d.vertex_refs.resize(d.vertices.size(), 0);
}

MeshData VtkXmlReader::read() {
  locate_appended();
  xml_ = std::make_unique<XmlDocument>(data_, xml_end_, path_);
  xml_->parse();
  read_header();
  const XmlElement& root = xml_->root();
  const int ds = xml_->child(root, poly_ ? "PolyData" : "UnstructuredGrid");
  if (ds < 0) fail(root, std::string("no <") + (poly_ ? "PolyData" : "UnstructuredGrid") + "> in <VTKFile>");
  MeshData d;
  for (int k : xml_->element(ds).children)
    if (xml_->element(k).name == "Piece") read_piece(xml_->element(k), d);
  for (FieldData& f : d.fields)
    if (f.values.size() != d.vertices.size() * static_cast<std::size_t>(f.info.ncomp))
      f.values.resize(d.vertices.size() * static_cast<std::size_t>(f.info.ncomp), 0.0);
  for (const auto& [what, count] : skipped_cells_)
    d.warnings.push_back(path_ + ": skipped " + std::to_string(count) + " " + what +
                         ", expected triangles and lines");
  for (const std::string& a : skipped_arrays_) d.warnings.push_back(path_ + ": skipped " + a);
  bool any_ref = false;
  for (int r : d.triangle_refs) any_ref |= r != 0;
  for (int r : d.edge_refs) any_ref |= r != 0;
  if (!any_ref) {
    d.triangle_refs.clear();
    d.edge_refs.clear();
  }
  return d;
}

// ------------------------------------------------------------- writing

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

class VtkXmlWriter {
 public:
  VtkXmlWriter(VtkXmlEncoding encoding, bool compress) : encoding_(encoding), compress_(compress && encoding != VtkXmlEncoding::Ascii) {}
  // A DataArray element of doubles or integers (type "Float64", "Int64",
  // "Int32", "UInt8").
  template <class T>
  void array(std::string& out, const std::string& indent, const char* type, const std::string& name, int ncomp,
             const std::vector<T>& values);
  std::string appended_section() const;

 private:
  std::string binary_text(const std::string& bytes) const;
  VtkXmlEncoding encoding_;
  bool compress_;
  std::string appended_;  // raw bytes or base64 text
};

constexpr std::size_t kBlockSize = 32768;

std::string uint64_bytes(std::uint64_t v) { return std::string(reinterpret_cast<const char*>(&v), 8); }

std::string VtkXmlWriter::binary_text(const std::string& bytes) const {
  if (!compress_) return encoding_ == VtkXmlEncoding::Appended ? uint64_bytes(bytes.size()) + bytes
                                                               : base64_encode(uint64_bytes(bytes.size()) + bytes);
  const CompressedArray c = zlib_compress_blocks(bytes, kBlockSize, 8);
  if (encoding_ == VtkXmlEncoding::Appended) return c.header + c.data;
  return base64_encode(c.header) + base64_encode(c.data);
}

template <class T>
void VtkXmlWriter::array(std::string& out, const std::string& indent, const char* type, const std::string& name,
                         int ncomp, const std::vector<T>& values) {
  out += indent + "<DataArray type=\"" + type + "\"";
  if (!name.empty()) out += " Name=\"" + xml_escape(name) + "\"";
  if (ncomp != 1) out += " NumberOfComponents=\"" + std::to_string(ncomp) + "\"";
  if (encoding_ == VtkXmlEncoding::Ascii) {
    out += " format=\"ascii\">\n" + indent + "  ";
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i) out += (i % static_cast<std::size_t>(ncomp * (ncomp == 1 ? 8 : 1)) == 0) ? "\n" + indent + "  " : " ";
      if constexpr (std::is_floating_point_v<T>)
        out += format_double(values[i]);
      else
        out += std::to_string(values[i]);
    }
    out += "\n" + indent + "</DataArray>\n";
    return;
  }
  const std::string bytes(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  if (encoding_ == VtkXmlEncoding::Binary) {
    out += " format=\"binary\">\n" + indent + "  " + binary_text(bytes) + "\n" + indent + "</DataArray>\n";
    return;
  }
  out += " format=\"appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
  appended_ += binary_text(bytes);  // raw bytes, or base64 text for AppendedBase64
}

std::string VtkXmlWriter::appended_section() const {
  if (encoding_ != VtkXmlEncoding::Appended && encoding_ != VtkXmlEncoding::AppendedBase64) return "";
  return std::string("  <AppendedData encoding=\"") + (encoding_ == VtkXmlEncoding::Appended ? "raw" : "base64") +
         "\">\n   _" + appended_ + "\n  </AppendedData>\n";
}

// Point data: vertex refs and fields.
void write_point_data(VtkXmlWriter& w, std::string& b, const MeshData& d) {
  if (d.vertex_refs.empty() && d.fields.empty()) return;
  b += "      <PointData>\n";
  const std::string in = "        ";
  if (!d.vertex_refs.empty()) {
    const std::vector<std::int32_t> refs(d.vertex_refs.begin(), d.vertex_refs.end());
    w.array(b, in, "Int32", "vertex_ref", 1, refs);
  }
  std::set<std::string> used{"vertex_ref"};
  for (std::size_t k = 0; k < d.fields.size(); ++k) {
    const FieldData& f = d.fields[k];
    std::string name = f.info.name.empty() ? "field" + std::to_string(k) : f.info.name;
    for (int i = 1; used.count(name); ++i) name = f.info.name + "_" + std::to_string(i);
    used.insert(name);
    const int nc = layout_components(f.info) ? layout_components(f.info) : f.info.ncomp;
    std::vector<double> values(d.vertices.size() * static_cast<std::size_t>(nc));
    for (std::size_t v = 0; v < d.vertices.size(); ++v) {
      if (layout_components(f.info))
        layout_values(f, v, values.data() + v * static_cast<std::size_t>(nc));
      else
        std::copy_n(f.values.data() + v * static_cast<std::size_t>(nc), nc, values.data() + v * static_cast<std::size_t>(nc));
    }
    w.array(b, in, "Float64", name, nc, values);
  }
  b += "      </PointData>\n";
}

void write_points(VtkXmlWriter& w, std::string& b, const MeshData& d) {
  std::vector<double> xyz;
  xyz.reserve(3 * d.vertices.size());
  for (const Vec3& p : d.vertices) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  b += "      <Points>\n";
  w.array(b, "        ", "Float64", "Points", 3, xyz);
  b += "      </Points>\n";
}

void write_cell_section(VtkXmlWriter& w, std::string& b, const char* section, const std::vector<std::int64_t>& conn,
                        const std::vector<std::int64_t>& offsets, const std::vector<std::uint8_t>* types) {
  b += std::string("      <") + section + ">\n";
  w.array(b, "        ", "Int64", "connectivity", 1, conn);
  w.array(b, "        ", "Int64", "offsets", 1, offsets);
  if (types) w.array(b, "        ", "UInt8", "types", 1, *types);
  b += std::string("      </") + section + ">\n";
}

std::string write_vtk_xml_body(const MeshData& d, bool poly, VtkXmlWriter& w) {
  const std::size_t nt = d.triangles.size(), ne = d.edges.size();
  const bool refs = !d.triangle_refs.empty() || !d.edge_refs.empty();
  auto tri_ref = [&](std::size_t i) { return d.triangle_refs.empty() ? 0 : d.triangle_refs[i]; };
  auto edge_ref = [&](std::size_t i) { return d.edge_refs.empty() ? 0 : d.edge_refs[i]; };
  std::string b;
  if (poly)
    b += "    <Piece NumberOfPoints=\"" + std::to_string(d.vertices.size()) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
         std::to_string(ne) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(nt) + "\">\n";
  else
    b += "    <Piece NumberOfPoints=\"" + std::to_string(d.vertices.size()) + "\" NumberOfCells=\"" +
         std::to_string(nt + ne) + "\">\n";
  write_point_data(w, b, d);
  if (refs) {
    std::vector<std::int32_t> r;
    if (poly) {  // cell order of PolyData: lines before polygons
      for (std::size_t i = 0; i < ne; ++i) r.push_back(edge_ref(i));
      for (std::size_t i = 0; i < nt; ++i) r.push_back(tri_ref(i));
    } else {
      for (std::size_t i = 0; i < nt; ++i) r.push_back(tri_ref(i));
      for (std::size_t i = 0; i < ne; ++i) r.push_back(edge_ref(i));
    }
    b += "      <CellData>\n";
    w.array(b, "        ", "Int32", "medit:ref", 1, r);
    b += "      </CellData>\n";
  }
  write_points(w, b, d);
  std::vector<std::int64_t> tri_conn, tri_off, edge_conn, edge_off;
  for (const auto& t : d.triangles) {
    tri_conn.insert(tri_conn.end(), {t[0], t[1], t[2]});
    tri_off.push_back(static_cast<std::int64_t>(tri_conn.size()));
  }
  for (const auto& e : d.edges) {
    edge_conn.insert(edge_conn.end(), {e[0], e[1]});
    edge_off.push_back(static_cast<std::int64_t>(edge_conn.size()));
  }
  if (poly) {
    write_cell_section(w, b, "Lines", edge_conn, edge_off, nullptr);
    write_cell_section(w, b, "Polys", tri_conn, tri_off, nullptr);
  } else {
    std::vector<std::int64_t> conn = tri_conn, off = tri_off;
    conn.insert(conn.end(), edge_conn.begin(), edge_conn.end());
    for (std::int64_t o : edge_off) off.push_back(o + static_cast<std::int64_t>(tri_conn.size()));
    std::vector<std::uint8_t> types(nt, 5);
    types.insert(types.end(), ne, 3);
    write_cell_section(w, b, "Cells", conn, off, &types);
  }
  b += "    </Piece>\n";
  return b;
}

}  // namespace

MeshData read_vtk_xml(const std::string& path) {
  VtkXmlReader reader(path);
  return reader.read();
}

void write_vtk_xml(const std::string& path, const MeshData& d, bool poly, VtkXmlEncoding encoding, bool compress) {
  check_for_writing(path, d, false);
  if (!host_is_little_endian()) throw IoError(path + ": VTK XML output needs a little-endian host");
  VtkXmlWriter w(encoding, compress);
  const char* type = poly ? "PolyData" : "UnstructuredGrid";
  const std::string body = write_vtk_xml_body(d, poly, w);
  std::string b = "<?xml version=\"1.0\"?>\n<VTKFile type=\"";
  b += type;
  b += "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  if (compress && encoding != VtkXmlEncoding::Ascii) b += " compressor=\"vtkZLibDataCompressor\"";
  b += ">\n  <" + std::string(type) + ">\n" + body + "  </" + type + ">\n" + w.appended_section() + "</VTKFile>\n";
  AtomicFile file(path);
  file.stream().write(b.data(), static_cast<std::streamsize>(b.size()));
  file.commit();
}

}  // namespace anisurf::io
