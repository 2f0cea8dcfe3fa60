// Gmsh MSH files, versions 2.2 and 4.1, ASCII and binary (either byte order
// on reading).
// Reading: $Nodes (vertices ordered by node tag), $Elements: triangles
// (type 2) with their physical tag as triangle ref, lines (type 1) as edges
// with their physical tag as edge ref, points (type 15) as corners with their
// physical tag as vertex ref; every other element type is skipped with a
// warning. The physical tag is the element's first tag (2.2) or the first
// physical tag of its entity in $Entities (4.1); 0 without one. Elements keep
// the order of their element tags. $NodeData: 1 component -> scalar field,
// 3 -> vector, 9 -> symmetric tensor (a non-symmetric one is made symmetric
// with a warning); the last $NodeData of a name wins; nodes without a value get
// 0 (warning). $PhysicalNames and other sections are skipped.
// Writing: node tags 1..n in vertex order; element tags in the order
// triangles, edges, corners. 4.1: one surface entity per triangle ref, one
// curve entity per edge ref, one point entity per corner, with the ref as
// physical tag (none for ref 0); each node classified on the first entity
// using it, the node blocks being the runs of consecutive nodes of one entity
// (nodes in tag order). 2.2: tags "physical elementary". Fields as $NodeData (scalars,
// vectors padded to 3 components, tensors as 9 components), the nodes in the
// order of $Nodes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/field_layout.h"
#include "io/formats.h"
#include "io/mixed_reader.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

constexpr long long kMaxTag = (1LL << 62);
constexpr int kLine = 1, kTriangle = 2, kPoint = 15;

// Nodes of the element types of the MSH format (0 for an unknown type).
int element_nodes(long long type) {
  static const int nodes[] = {0,  2,  3,  4,  4,  8,   6,  5,  3,  6,  9,  10, 27, 18, 14, 1,
                              8,  20, 15, 13, 9,  10,  12, 15, 15, 21, 4,  5,  6,  20, 35, 56};
  if (type >= 0 && type < static_cast<long long>(sizeof nodes / sizeof nodes[0])) return nodes[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

struct Element {
  long long tag = 0;
  int type = 0;
  int physical = 0;
  std::vector<long long> nodes;
};

struct NodeDataBlock {
  std::string name;
  int ncomp = 0;
  std::vector<std::pair<long long, std::vector<double>>> values;  // node tag, components
};

class MshReader {
 public:
  explicit MshReader(const std::string& path) : r_(read_file_contents(path), path) {}
  MeshData read();

 private:
  void read_format();
  void read_entities();
  void read_nodes_v2();
  void read_nodes_v4();
  void read_elements_v2();
  void read_elements_v4();
  void read_node_data();
  void skip_section(std::string_view name);
  void end_section(const char* name);
  void add_element(Element e);
  void finish(MeshData& d);

  // A value of the section data: text token or binary value of the file.
  long long get_int(const char* what, long long lo, long long hi);
  long long get_size(const char* what, long long lo, long long hi);
  double get_double(const char* what);
  void set_data_mode(bool data) { r_.set_binary(binary_ && data); }

  MixedReader r_;
  int version_ = 0;  // 22 or 41
  bool binary_ = false;
  bool swap_ = false;
  int size_bytes_ = 8;
  std::vector<std::pair<long long, Vec3>> nodes_;  // tag, position
  std::map<std::pair<int, long long>, int> entity_physical_;
  std::vector<Element> elements_;
  std::map<int, long long> skipped_;
  std::vector<NodeDataBlock> node_data_;
  bool have_nodes_ = false;
};

long long MshReader::get_int(const char* what, long long lo, long long hi) {
  if (!binary_) return r_.read_int(what, lo, hi);
  const long long v = r_.read<std::int32_t>(what, swap_);
  if (v < lo || v > hi)
    r_.fail(std::string(what) + " " + std::to_string(v) + " out of range, expected " + std::to_string(lo) + ".." +
            std::to_string(hi));
  return v;
}

long long MshReader::get_size(const char* what, long long lo, long long hi) {
  if (!binary_) return r_.read_int(what, lo, hi);
  unsigned long long v = size_bytes_ == 8 ? r_.read<std::uint64_t>(what, swap_) : r_.read<std::uint32_t>(what, swap_);
  if (v > static_cast<unsigned long long>(hi) || static_cast<long long>(v) < lo)
    r_.fail(std::string(what) + " " + std::to_string(v) + " out of range, expected " + std::to_string(lo) + ".." +
            std::to_string(hi));
  return static_cast<long long>(v);
}

double MshReader::get_double(const char* what) {
  const double v = binary_ ? r_.read<double>(what, swap_) : r_.read_double(what);
  if (!std::isfinite(v)) r_.fail(std::string(what) + " is not a finite number");
  return v;
}

void MshReader::read_format() {
  const std::string_view first = r_.token("'$MeshFormat'");
  if (first != "$MeshFormat") r_.fail_expected("'$MeshFormat' (a Gmsh .msh file)", first);
  const std::string_view v = r_.token("version");
  if (v == "2.2" || v == "2.1" || v == "2" || v == "2.0")
    version_ = 22;
  else if (v == "4.1")
    version_ = 41;
  else
    r_.fail_expected("MSH version 2.2 or 4.1", v);
  binary_ = r_.read_int("file type (0 ASCII, 1 binary)", 0, 1) == 1;
  size_bytes_ = static_cast<int>(r_.read_int("data size", 4, 8));
  if (size_bytes_ != 4 && size_bytes_ != 8) r_.fail("data size " + std::to_string(size_bytes_) + ", expected 4 or 8");
  if (binary_) {
    r_.skip_line_end();
    r_.set_binary(true);
    std::int32_t one = r_.read<std::int32_t>("the binary int 1", false);
    if (one != 1) {
      std::int32_t swapped = 0;
      for (int i = 0; i < 4; ++i) reinterpret_cast<char*>(&swapped)[i] = reinterpret_cast<const char*>(&one)[3 - i];
      if (swapped != 1) r_.fail("the binary int is " + std::to_string(one) + ", expected 1 (in either byte order)");
      swap_ = true;
    }
  }
  end_section("$EndMeshFormat");
}

void MshReader::end_section(const char* name) {
  r_.skip_space();
  const std::string_view t = r_.token(name);
  if (t != name) r_.fail_expected((std::string("'") + name + "'").c_str(), t);
}

void MshReader::skip_section(std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  if (!r_.skip_past(end)) r_.fail("section " + std::string(name) + " without '" + end + "'");
}

void MshReader::read_entities() {
  if (binary_) r_.skip_line_end();
  set_data_mode(true);
  const long long hi = static_cast<long long>(r_.size());
  long long counts[4];
  for (long long& c : counts) c = get_size("entity count", 0, hi);
  for (int dim = 0; dim < 4; ++dim) {
    r_.check_fits(counts[dim], binary_ ? 4 + 8 * (dim ? 6 : 3) + 8 : 5, "entity");
    for (long long i = 0; i < counts[dim]; ++i) {
      const long long tag = get_int("entity tag", -kMaxTag, kMaxTag);
      for (int k = 0; k < (dim ? 6 : 3); ++k) get_double(dim ? "bounding box coordinate" : "point coordinate");
      const long long n_phys = get_size("physical tag count", 0, hi);
      r_.check_fits(n_phys, binary_ ? 4 : 2, "physical tag");
      int physical = 0;
      for (long long k = 0; k < n_phys; ++k) {
        const long long p = get_int("physical tag", INT32_MIN, INT32_MAX);
        if (k == 0) physical = static_cast<int>(p);
      }
      entity_physical_[{dim, tag}] = physical;
      if (dim > 0) {
        const long long n_bound = get_size("bounding entity count", 0, hi);
        r_.check_fits(n_bound, binary_ ? 4 : 2, "bounding entity");
        for (long long k = 0; k < n_bound; ++k) get_int("bounding entity tag", -kMaxTag, kMaxTag);
      }
    }
  }
  set_data_mode(false);
  end_section("$EndEntities");
}

void MshReader::read_nodes_v2() {
  const long long n = r_.read_int("node count", 0, kMaxTag);
  r_.check_fits(n, binary_ ? 28 : 8, "node");
  if (binary_) r_.skip_line_end();
  set_data_mode(true);
  nodes_.reserve(static_cast<std::size_t>(n));
  for (long long i = 0; i < n; ++i) {
    const long long tag = get_int("node tag", 1, kMaxTag);
    Vec3 p;
    p.x = get_double("node x coordinate");
    p.y = get_double("node y coordinate");
    p.z = get_double("node z coordinate");
    nodes_.push_back({tag, p});
  }
  set_data_mode(false);
  end_section("$EndNodes");
}

void MshReader::read_nodes_v4() {
  if (binary_) r_.skip_line_end();
  set_data_mode(true);
  const long long hi = static_cast<long long>(r_.size());
  const long long blocks = get_size("node block count", 0, hi);
  const long long n = get_size("node count", 0, kMaxTag);
  r_.check_fits(n, binary_ ? 32 : 8, "node");
  get_size("minimum node tag", 0, kMaxTag);
  get_size("maximum node tag", 0, kMaxTag);
  nodes_.reserve(static_cast<std::size_t>(n));
  for (long long b = 0; b < blocks; ++b) {
    const long long dim = get_int("entity dimension", 0, 3);
    get_int("entity tag", -kMaxTag, kMaxTag);
    const bool parametric = get_int("parametric flag (0 or 1)", 0, 1) == 1;
    const long long count = get_size("node count of the block", 0, hi);
    const int extra = parametric ? static_cast<int>(dim == 1 ? 1 : dim == 2 ? 2 : 0) : 0;
    r_.check_fits(count, binary_ ? static_cast<std::size_t>(8 + 8 * (3 + extra)) : 8, "node");
    if (static_cast<long long>(nodes_.size()) + count > n)
      r_.fail("node blocks hold more than the " + std::to_string(n) + " nodes announced, expected " +
              std::to_string(n));
    const std::size_t first = nodes_.size();
    for (long long i = 0; i < count; ++i) nodes_.push_back({get_size("node tag", 1, kMaxTag), Vec3{}});
    for (long long i = 0; i < count; ++i) {
      Vec3& p = nodes_[first + static_cast<std::size_t>(i)].second;
      p.x = get_double("node x coordinate");
      p.y = get_double("node y coordinate");
      p.z = get_double("node z coordinate");
      for (int k = 0; k < extra; ++k) get_double("parametric coordinate");
    }
  }
  if (static_cast<long long>(nodes_.size()) != n)
    r_.fail("node blocks hold " + std::to_string(nodes_.size()) + " nodes, expected " + std::to_string(n));
  set_data_mode(false);
  end_section("$EndNodes");
}

void MshReader::add_element(Element e) {
  if (e.type == kTriangle || e.type == kLine || e.type == kPoint)
    elements_.push_back(std::move(e));
  else
    ++skipped_[e.type];
}

void MshReader::read_elements_v2() {
  const long long n = r_.read_int("element count", 0, kMaxTag);
  r_.check_fits(n, binary_ ? 12 : 6, "element");
  if (!binary_) {
    for (long long i = 0; i < n; ++i) {
      Element e;
      e.tag = r_.read_int("element tag", 1, kMaxTag);
      e.type = static_cast<int>(r_.read_int("element type", 1, 1000));
      const long long n_tags = r_.read_int("element tag count", 0, 1000);
      for (long long k = 0; k < n_tags; ++k) {
        const long long t = r_.read_int("element tag", INT32_MIN, INT32_MAX);
        if (k == 0) e.physical = static_cast<int>(t);
      }
      const int nn = element_nodes(e.type);
      if (nn == 0 || (e.type != kTriangle && e.type != kLine && e.type != kPoint)) {
        r_.rest_of_line();
        ++skipped_[e.type];
        continue;
      }
      for (int k = 0; k < nn; ++k) e.nodes.push_back(r_.read_int("element node tag", 1, kMaxTag));
      add_element(std::move(e));
    }
  } else {
    r_.skip_line_end();
    set_data_mode(true);
    long long done = 0;
    while (done < n) {
      const int type = static_cast<int>(get_int("element type", 1, 1000));
      const long long count = get_int("element count of the block", 1, n - done);
      const long long n_tags = get_int("element tag count", 0, 1000);
      const int nn = element_nodes(type);
      if (nn == 0) r_.fail("unknown element type " + std::to_string(type) + ", expected a type of the MSH format");
      r_.check_fits(count, static_cast<std::size_t>(4 * (1 + n_tags + nn)), "element");
      for (long long i = 0; i < count; ++i) {
        Element e;
        e.type = type;
        e.tag = get_int("element tag", 1, kMaxTag);
        for (long long k = 0; k < n_tags; ++k) {
          const long long t = get_int("element tag", INT32_MIN, INT32_MAX);
          if (k == 0) e.physical = static_cast<int>(t);
        }
        for (int k = 0; k < nn; ++k) e.nodes.push_back(get_int("element node tag", 1, kMaxTag));
        add_element(std::move(e));
      }
      done += count;
    }
    set_data_mode(false);
  }
  end_section("$EndElements");
}

void MshReader::read_elements_v4() {
  if (binary_) r_.skip_line_end();
  set_data_mode(true);
  const long long hi = static_cast<long long>(r_.size());
  const long long blocks = get_size("element block count", 0, hi);
  const long long n = get_size("element count", 0, kMaxTag);
  r_.check_fits(n, binary_ ? 16 : 4, "element");
  get_size("minimum element tag", 0, kMaxTag);
  get_size("maximum element tag", 0, kMaxTag);
  long long done = 0;
  for (long long b = 0; b < blocks; ++b) {
    const int dim = static_cast<int>(get_int("entity dimension", 0, 3));
    const long long entity = get_int("entity tag", -kMaxTag, kMaxTag);
    const int type = static_cast<int>(get_int("element type", 1, 1000));
    const long long count = get_size("element count of the block", 0, n - done);
    const int nn = element_nodes(type);
    const bool kept = type == kTriangle || type == kLine || type == kPoint;
    if (nn == 0 && binary_)
      r_.fail("unknown element type " + std::to_string(type) + ", expected a type of the MSH format");
    r_.check_fits(count, binary_ ? static_cast<std::size_t>(8 * (1 + nn)) : 2, "element");
    const auto found = entity_physical_.find({dim, entity});
    const int physical = found == entity_physical_.end() ? 0 : found->second;
    for (long long i = 0; i < count; ++i) {
      if (!kept && !binary_) {
        r_.token("element tag");
        r_.rest_of_line();
        ++skipped_[type];
        continue;
      }
      Element e;
      e.type = type;
      e.physical = physical;
      e.tag = get_size("element tag", 1, kMaxTag);
      for (int k = 0; k < nn; ++k) e.nodes.push_back(get_size("element node tag", 1, kMaxTag));
      add_element(std::move(e));
    }
    done += count;
  }
  if (done != n) r_.fail("element blocks hold " + std::to_string(done) + " elements, expected " + std::to_string(n));
  set_data_mode(false);
  end_section("$EndElements");
}

std::string unquoted(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

void MshReader::read_node_data() {
  if (!have_nodes_) r_.fail("$NodeData before $Nodes, expected $Nodes first");
  NodeDataBlock block;
  const long long n_strings = r_.read_int("string tag count", 0, 1000);
  r_.skip_line_end();
  for (long long i = 0; i < n_strings; ++i) {
    const std::string s = unquoted(r_.rest_of_line());
    if (i == 0) block.name = s;
  }
  const long long n_reals = r_.read_int("real tag count", 0, 1000);
  for (long long i = 0; i < n_reals; ++i) r_.read_double("real tag");
  const long long n_ints = r_.read_int("integer tag count", 3, 1000);
  long long ints[3] = {0, 0, 0};
  for (long long i = 0; i < n_ints; ++i) {
    const long long v = r_.read_int("integer tag", INT32_MIN, kMaxTag);
    if (i < 3) ints[i] = v;
  }
  const long long nc = ints[1], n = ints[2];
  if (nc < 1 || nc > 9) r_.fail("$NodeData has " + std::to_string(nc) + " components, expected 1, 3 or 9");
  if (n < 0) r_.fail("$NodeData has " + std::to_string(n) + " values, expected a count >= 0");
  block.ncomp = static_cast<int>(nc);
  r_.check_fits(n, binary_ ? static_cast<std::size_t>(4 + 8 * nc) : static_cast<std::size_t>(2 * (1 + nc)),
                "node value");
  if (binary_) r_.skip_line_end();
  set_data_mode(true);
  block.values.reserve(static_cast<std::size_t>(n));
  for (long long i = 0; i < n; ++i) {
    const long long tag = get_int("node tag", 1, kMaxTag);
    std::vector<double> v(static_cast<std::size_t>(nc));
    for (double& x : v) x = get_double("node value");
    block.values.push_back({tag, std::move(v)});
  }
  set_data_mode(false);
  end_section("$EndNodeData");
  node_data_.push_back(std::move(block));
}

// Vertex ids of node tags: the nodes in increasing tag order.
std::unordered_map<long long, int> index_nodes(std::vector<std::pair<long long, Vec3>>& nodes,
                                                const std::string& path) {
  std::stable_sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::unordered_map<long long, int> index;
  index.reserve(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!index.emplace(nodes[i].first, static_cast<int>(i)).second)
      throw IoError(path + ": node tag " + std::to_string(nodes[i].first) +
                    " defined twice in $Nodes, expected distinct node tags");
  return index;
}

std::string element_name(int type) {
  switch (type) {
    case 3: return "quadrangles (type 3)";
    case 4: return "tetrahedra (type 4)";
    case 5: return "hexahedra (type 5)";
    case 6: return "prisms (type 6)";
    case 7: return "pyramids (type 7)";
    case 8: return "second-order lines (type 8)";
    case 9: return "second-order triangles (type 9)";
    default: return "elements of type " + std::to_string(type);
  }
}

void MshReader::finish(MeshData& d) {
  const std::string& path = r_.path();
  const auto index = index_nodes(nodes_, path);
  d.vertices.reserve(nodes_.size());
  for (const auto& n : nodes_) d.vertices.push_back(n.second);
  std::stable_sort(elements_.begin(), elements_.end(), [](const Element& a, const Element& b) { return a.tag < b.tag; });
  auto vertex = [&](const Element& e, long long tag) {
    const auto it = index.find(tag);
    if (it == index.end())
      throw IoError(path + ": element " + std::to_string(e.tag) + ": node tag " + std::to_string(tag) +
                    " not in $Nodes, expected a node tag of $Nodes");
    return it->second;
  };
  bool vertex_refs = false;
  for (const Element& e : elements_) {
    if (e.type == kTriangle) {
      d.triangles.push_back({vertex(e, e.nodes[0]), vertex(e, e.nodes[1]), vertex(e, e.nodes[2])});
      d.triangle_refs.push_back(e.physical);
    } else if (e.type == kLine) {
      d.edges.push_back({vertex(e, e.nodes[0]), vertex(e, e.nodes[1])});
      d.edge_refs.push_back(e.physical);
    } else {
      const int v = vertex(e, e.nodes[0]);
      d.corners.push_back(v);
      if (e.physical != 0) {
        if (!vertex_refs) d.vertex_refs.assign(d.vertices.size(), 0);
        vertex_refs = true;
        d.vertex_refs[static_cast<std::size_t>(v)] = e.physical;
      }
    }
  }
  for (const auto& [type, count] : skipped_)
    d.warnings.push_back(path + ": skipped " + std::to_string(count) + " " + element_name(type) +
                         ", expected triangles (2), lines (1) or points (15)");
  const std::size_t nv = d.vertices.size();
  for (NodeDataBlock& b : node_data_) {
    std::vector<double> values(nv * static_cast<std::size_t>(b.ncomp), 0.0);
    std::vector<char> set(nv, 0);
    for (const auto& [tag, v] : b.values) {
      const auto it = index.find(tag);
      if (it == index.end())
        throw IoError(path + ": $NodeData '" + b.name + "': node tag " + std::to_string(tag) +
                      " not in $Nodes, expected a node tag of $Nodes");
      std::copy(v.begin(), v.end(), values.begin() + static_cast<std::ptrdiff_t>(it->second) * b.ncomp);
      set[static_cast<std::size_t>(it->second)] = 1;
    }
    const auto missing = std::count(set.begin(), set.end(), 0);
    if (missing > 0)
      d.warnings.push_back(path + ": $NodeData '" + b.name + "': " + std::to_string(missing) +
                           " nodes without a value, set to 0");
    FieldData f;
    long long asymmetric = 0;
    if (!field_from_layout(b.name, b.ncomp, values, f, &asymmetric)) {
      d.warnings.push_back(path + ": skipped $NodeData '" + b.name + "' of " + std::to_string(b.ncomp) +
                           " components, expected 1 (scalar), 3 (vector) or 9 (tensor)");
      continue;
    }
    if (asymmetric > 0) d.warnings.push_back(asymmetric_warning(path, b.name, asymmetric));
    auto same = std::find_if(d.fields.begin(), d.fields.end(), [&](const FieldData& g) { return g.info.name == f.info.name; });
    if (same != d.fields.end()) {
      d.warnings.push_back(path + ": several $NodeData '" + b.name + "', the last one kept");
      *same = std::move(f);
    } else {
      d.fields.push_back(std::move(f));
    }
  }
}

MeshData MshReader::read() {
  read_format();
  while (!r_.at_end()) {
    r_.set_binary(false);
    const std::string_view section = r_.token("a section");
    if (section.empty() || section[0] != '$') r_.fail_expected("a section ('$Nodes', '$Elements' ...)", section);
    if (section == "$Nodes") {
      if (have_nodes_) r_.fail("second $Nodes section, expected one");
      version_ == 41 ? read_nodes_v4() : read_nodes_v2();
      have_nodes_ = true;
    } else if (section == "$Elements") {
      if (!have_nodes_) r_.fail("$Elements before $Nodes, expected $Nodes first");
      version_ == 41 ? read_elements_v4() : read_elements_v2();
    } else if (section == "$Entities" && version_ == 41) {
      read_entities();
    } else if (section == "$NodeData") {
      read_node_data();
    } else {
      skip_section(section);
    }
  }
  if (!have_nodes_) r_.fail("no $Nodes section, expected one");
  MeshData d;
  finish(d);
  return d;
}

// ---------------------------------------------------------------- writing

// Text or binary output of the values of a section.
class MshWriter {
 public:
  explicit MshWriter(bool binary) : binary_(binary) {}
  // Text written as is (section keywords, the text headers of a section).
  void text(std::string_view s) { b_ += s; }
  // Values: int (4 bytes), size_t (8 bytes) and double in binary; decimal
  // words separated by blanks in ASCII (doubles shortest exact).
  void int32(long long v) {
    if (binary_) raw(static_cast<std::int32_t>(v));
    else word(std::to_string(v));
  }
  void size(long long v) {
    if (binary_) raw(static_cast<std::uint64_t>(v));
    else word(std::to_string(v));
  }
  void real(double v) {
    if (binary_) raw(v);
    else word(format_double(v));
  }
  // End of a group of values (a line in ASCII, nothing in binary).
  void end_line() {
    if (!binary_) {
      b_ += '\n';
      first_ = true;
    }
  }
  // Back to text after binary values (a newline before the $End line).
  void end_data() {
    if (binary_) b_ += '\n';
  }
  std::string& buffer() { return b_; }

 private:
  template <class T>
  void raw(T v) {
    b_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void word(const std::string& s) {
    if (!first_) b_ += ' ';
    b_ += s;
    first_ = false;
  }
  bool binary_;
  bool first_ = true;
  std::string b_;
};

struct Entity {
  int dim = 0;
  int tag = 0;
  int physical = 0;
  std::vector<int> elements;  // ids into triangles, edges or corners
  std::vector<int> nodes;     // vertices in this entity's node block
};

struct MshLayout {
  std::vector<Entity> entities;  // surfaces, curves, points (element order)
  std::vector<int> owner;        // per vertex: the entity whose node block holds it
};

// One entity per distinct ref (surfaces and curves), one point per corner;
// each vertex in the node block of the first entity using it.
MshLayout msh_layout(const MeshData& d) {
  MshLayout l;
  auto group = [&](int dim, std::size_t n, const std::vector<int>& refs) {
    std::map<int, std::size_t> by_ref;
    for (std::size_t i = 0; i < n; ++i) {
      const int ref = refs.empty() ? 0 : refs[i];
      auto [it, added] = by_ref.emplace(ref, l.entities.size());
      if (added) l.entities.push_back({dim, static_cast<int>(by_ref.size()), ref, {}, {}});
      l.entities[it->second].elements.push_back(static_cast<int>(i));
    }
  };
  group(2, d.triangles.size(), d.triangle_refs);
  group(1, d.edges.size(), d.edge_refs);
  for (std::size_t i = 0; i < d.corners.size(); ++i) {
    const int v = d.corners[i];
    const int ref = d.vertex_refs.empty() ? 0 : d.vertex_refs[static_cast<std::size_t>(v)];
    l.entities.push_back({0, static_cast<int>(i + 1), ref, {static_cast<int>(i)}, {}});
  }
  if (l.entities.empty() && !d.vertices.empty()) l.entities.push_back({2, 1, 0, {}, {}});
  l.owner.assign(d.vertices.size(), -1);
  for (std::size_t i = 0; i < l.entities.size(); ++i) {
    Entity& e = l.entities[i];
    for (int el : e.elements) {
      const auto k = static_cast<std::size_t>(el);
      const int* vs = e.dim == 2 ? d.triangles[k].data() : e.dim == 1 ? d.edges[k].data() : &d.corners[k];
      for (int j = 0; j < (e.dim == 0 ? 1 : e.dim + 1); ++j)
        if (l.owner[static_cast<std::size_t>(vs[j])] < 0) {
          l.owner[static_cast<std::size_t>(vs[j])] = static_cast<int>(i);
          e.nodes.push_back(vs[j]);
        }
    }
  }
  for (std::size_t v = 0; v < l.owner.size(); ++v)
    if (l.owner[v] < 0) {
      l.owner[v] = 0;
      l.entities.front().nodes.push_back(static_cast<int>(v));
    }
  return l;
}

// Element tags: triangles 1..nt, then edges, then corners.
long long element_tag(const MeshData& d, int dim, int id) {
  if (dim == 2) return id + 1;
  if (dim == 1) return static_cast<long long>(d.triangles.size()) + id + 1;
  return static_cast<long long>(d.triangles.size() + d.edges.size()) + id + 1;
}

const int* element_vertices(const MeshData& d, int dim, int id) {
  const auto k = static_cast<std::size_t>(id);
  return dim == 2 ? d.triangles[k].data() : dim == 1 ? d.edges[k].data() : &d.corners[k];
}

int element_type(int dim) { return dim == 2 ? kTriangle : dim == 1 ? kLine : kPoint; }

void write_format(MshWriter& w, bool binary, const char* version) {
  w.text(std::string("$MeshFormat\n") + version + (binary ? " 1 8\n" : " 0 8\n"));
  if (binary) {
    w.int32(1);
    w.end_data();
  }
  w.text("$EndMeshFormat\n");
}

void write_entities_v4(MshWriter& w, const MeshData& d, const MshLayout& l, bool binary) {
  w.text("$Entities\n");
  long long count[4] = {0, 0, 0, 0};
  for (const Entity& e : l.entities) ++count[e.dim];
  for (long long c : count) w.size(c);
  w.end_line();
  for (int dim = 0; dim < 3; ++dim)
    for (const Entity& e : l.entities) {
      if (e.dim != dim) continue;
      w.int32(e.tag);
      Vec3 lo{0, 0, 0}, hi{0, 0, 0};
      for (std::size_t i = 0; i < e.nodes.size(); ++i) {
        const Vec3& p = d.vertices[static_cast<std::size_t>(e.nodes[i])];
        if (i == 0) lo = hi = p;
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
      if (dim == 0) lo = d.vertices[static_cast<std::size_t>(d.corners[static_cast<std::size_t>(e.elements[0])])];
      for (double c : {lo.x, lo.y, lo.z}) w.real(c);
      if (dim > 0)
        for (double c : {hi.x, hi.y, hi.z}) w.real(c);
      w.size(e.physical != 0 ? 1 : 0);
      if (e.physical != 0) w.int32(e.physical);
      if (dim > 0) w.size(0);
      w.end_line();
    }
  if (binary) w.end_data();
  w.text("$EndEntities\n");
}

// Node blocks: runs of consecutive vertices owned by the same entity, so that
// the nodes come in tag order (1..n) and each sits in its entity's block.
void write_nodes_v4(MshWriter& w, const MeshData& d, const MshLayout& l, bool binary) {
  w.text("$Nodes\n");
  const std::size_t nv = d.vertices.size();
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // [first, end)
  for (std::size_t v = 0; v < nv; ++v)
    if (runs.empty() || l.owner[v] != l.owner[runs.back().first])
      runs.push_back({v, v + 1});
    else
      runs.back().second = v + 1;
  w.size(static_cast<long long>(runs.size()));
  w.size(static_cast<long long>(nv));
  w.size(nv ? 1 : 0);
  w.size(static_cast<long long>(nv));
  w.end_line();
  for (const auto& [first, end] : runs) {
    const Entity& e = l.entities[static_cast<std::size_t>(l.owner[first])];
    w.int32(e.dim);
    w.int32(e.tag);
    w.int32(0);
    w.size(static_cast<long long>(end - first));
    w.end_line();
    for (std::size_t v = first; v < end; ++v) {
      w.size(static_cast<long long>(v) + 1);
      w.end_line();
    }
    for (std::size_t v = first; v < end; ++v) {
      const Vec3& p = d.vertices[v];
      w.real(p.x);
      w.real(p.y);
      w.real(p.z);
      w.end_line();
    }
  }
  if (binary) w.end_data();
  w.text("$EndNodes\n");
}

void write_elements_v4(MshWriter& w, const MeshData& d, const MshLayout& l, bool binary) {
  w.text("$Elements\n");
  long long blocks = 0;
  for (const Entity& e : l.entities) blocks += !e.elements.empty();
  const auto ne = static_cast<long long>(d.triangles.size() + d.edges.size() + d.corners.size());
  w.size(blocks);
  w.size(ne);
  w.size(ne ? 1 : 0);
  w.size(ne);
  w.end_line();
  for (const Entity& e : l.entities) {
    if (e.elements.empty()) continue;
    w.int32(e.dim);
    w.int32(e.tag);
    w.int32(element_type(e.dim));
    w.size(static_cast<long long>(e.elements.size()));
    w.end_line();
    const int nn = e.dim == 0 ? 1 : e.dim + 1;
    for (int id : e.elements) {
      w.size(element_tag(d, e.dim, id));
      const int* vs = element_vertices(d, e.dim, id);
      for (int k = 0; k < nn; ++k) w.size(vs[k] + 1);
      w.end_line();
    }
  }
  if (binary) w.end_data();
  w.text("$EndElements\n");
}

void write_nodes_v2(MshWriter& w, const MeshData& d, bool binary) {
  w.text("$Nodes\n" + std::to_string(d.vertices.size()) + "\n");
  for (std::size_t v = 0; v < d.vertices.size(); ++v) {
    w.int32(static_cast<long long>(v) + 1);
    w.real(d.vertices[v].x);
    w.real(d.vertices[v].y);
    w.real(d.vertices[v].z);
    w.end_line();
  }
  if (binary) w.end_data();
  w.text("$EndNodes\n");
}

void write_elements_v2(MshWriter& w, const MeshData& d, const MshLayout& l, bool binary) {
  // Elements in tag order; the elementary tag is the 4.1 layout's entity tag.
  struct Item {
    int dim, id, physical, entity;
  };
  std::vector<Item> items;
  for (const Entity& e : l.entities)
    for (int id : e.elements) items.push_back({e.dim, id, e.physical, e.tag});
  std::stable_sort(items.begin(), items.end(), [&](const Item& a, const Item& b) {
    return element_tag(d, a.dim, a.id) < element_tag(d, b.dim, b.id);
  });
  w.text("$Elements\n" + std::to_string(items.size()) + "\n");
  for (std::size_t i = 0; i < items.size();) {
    std::size_t j = i;
    while (j < items.size() && items[j].dim == items[i].dim) ++j;
    if (binary) {
      w.int32(element_type(items[i].dim));
      w.int32(static_cast<long long>(j - i));
      w.int32(2);
    }
    const int nn = items[i].dim == 0 ? 1 : items[i].dim + 1;
    for (std::size_t k = i; k < j; ++k) {
      const Item& it = items[k];
      w.int32(element_tag(d, it.dim, it.id));
      if (!binary) {
        w.int32(element_type(it.dim));
        w.int32(2);
      }
      w.int32(it.physical);
      w.int32(it.entity);
      const int* vs = element_vertices(d, it.dim, it.id);
      for (int c = 0; c < nn; ++c) w.int32(vs[c] + 1);
      w.end_line();
    }
    i = j;
  }
  if (binary) w.end_data();
  w.text("$EndElements\n");
}

// $NodeData of every field, the nodes in tag order (the order of $Nodes: some
// readers take the values in that order whatever their tags).
void write_node_data(MshWriter& w, const MeshData& d, bool binary) {
  for (const FieldData& f : d.fields) {
    const int nc = layout_components(f.info);
    std::string name = f.info.name;
    std::replace(name.begin(), name.end(), '"', '\'');
    std::replace(name.begin(), name.end(), '\n', ' ');
    w.text("$NodeData\n1\n\"" + name + "\"\n1\n0\n3\n0\n" + std::to_string(nc) + "\n" +
           std::to_string(d.vertices.size()) + "\n");
    double v[9];
    for (std::size_t i = 0; i < d.vertices.size(); ++i) {
      w.int32(static_cast<long long>(i) + 1);
      layout_values(f, i, v);
      for (int c = 0; c < nc; ++c) w.real(v[c]);
      w.end_line();
    }
    if (binary) w.end_data();
    w.text("$EndNodeData\n");
  }
}

}  // namespace

MeshData read_gmsh(const std::string& path) {
  MshReader reader(path);
  return reader.read();
}

void write_gmsh(const std::string& path, const MeshData& d, int version, bool binary) {
  if (version != 41 && version != 22)
    throw IoError(path + ": cannot write MSH version " + std::to_string(version) + ", expected 4.1 or 2.2");
  check_for_writing(path, d, true);
  if (binary && !host_is_little_endian()) throw IoError(path + ": binary MSH output needs a little-endian host");
  const MshLayout layout = msh_layout(d);
  MshWriter w(binary);
  w.buffer().reserve(64 * (d.vertices.size() * (1 + d.fields.size()) + d.triangles.size()) + 256);
  write_format(w, binary, version == 41 ? "4.1" : "2.2");
  if (version == 41) {
    write_entities_v4(w, d, layout, binary);
    write_nodes_v4(w, d, layout, binary);
    write_elements_v4(w, d, layout, binary);
  } else {
    write_nodes_v2(w, d, binary);
    write_elements_v2(w, d, layout, binary);
  }
  write_node_data(w, d, binary);
  AtomicFile file(path);
  file.stream().write(w.buffer().data(), static_cast<std::streamsize>(w.buffer().size()));
  file.commit();
}

}  // namespace anisurf::io
