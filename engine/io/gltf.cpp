// glTF 2.0 (.gltf with external or embedded buffers, .glb) through tinygltf.
// Reading: the triangles of every mesh primitive (TRIANGLES, TRIANGLE_STRIP,
// TRIANGLE_FAN; indexed or not) of every node of the scene, with the node
// transforms accumulated from the roots; a mesh used by several nodes appears
// once per node. Images are never read; external buffers are read as
// gltf_buffers.h allows (regular files under the .gltf's directory, of their
// declared size). Writing (.glb): one mesh with one primitive, float POSITION
// and uint32 indices, written by hand.
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/formats.h"
#include "io/gltf_buffers.h"
#include "io/text_reader.h"

namespace anisurf::io {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

// Column-major 4x4 matrix, as glTF stores node matrices.
using Mat4 = std::array<double, 16>;

Mat4 identity() {
  Mat4 m{};
  m[0] = m[5] = m[10] = m[15] = 1;
  return m;
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[col * 4 + k];
      c[col * 4 + row] = s;
    }
  return c;
}

Vec3 transform_point(const Mat4& m, const Vec3& p) {
  return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
          m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}

double det3(const Mat4& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
         m[8] * (m[1] * m[6] - m[5] * m[2]);
}

// Local transform of a node: its matrix, or translation * rotation * scale.
Mat4 local_transform(const tinygltf::Node& n, int index, const std::string& path) {
  auto bad = [&](const char* what, std::size_t size, int expected) {
    throw IoError(path + ": node " + std::to_string(index) + ": " + what + " has " + std::to_string(size) +
                  " numbers, expected " + std::to_string(expected));
  };
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) bad("matrix", n.matrix.size(), 16);
    Mat4 m;
    for (int i = 0; i < 16; ++i) m[i] = n.matrix[i];
    return m;
  }
  if (!n.translation.empty() && n.translation.size() != 3) bad("translation", n.translation.size(), 3);
  if (!n.rotation.empty() && n.rotation.size() != 4) bad("rotation", n.rotation.size(), 4);
  if (!n.scale.empty() && n.scale.size() != 3) bad("scale", n.scale.size(), 3);
  double s[3] = {1, 1, 1};
  if (!n.scale.empty()) s[0] = n.scale[0], s[1] = n.scale[1], s[2] = n.scale[2];
  double x = 0, y = 0, z = 0, w = 1;
  if (!n.rotation.empty()) {
    x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (len > 0) x /= len, y /= len, z /= len, w /= len;
  }
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  Mat4 m = identity();
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) m[col * 4 + row] = r[row][col] * s[col];
  if (!n.translation.empty()) m[12] = n.translation[0], m[13] = n.translation[1], m[14] = n.translation[2];
  return m;
}

// Bytes of an accessor, checked against its buffer view and buffer.
struct AccessorData {
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
  int component_type = 0;
};

AccessorData accessor_data(const tinygltf::Model& model, int index, const std::string& where) {
  auto fail = [&](const std::string& msg) { throw IoError(where + ": accessor " + std::to_string(index) + ": " + msg); };
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
    throw IoError(where + ": accessor index " + std::to_string(index) + " out of range, expected 0.." +
                  std::to_string(static_cast<long long>(model.accessors.size()) - 1));
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
  if (a.sparse.isSparse) fail("sparse accessors are not supported, expected a plain accessor");
  if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= model.bufferViews.size())
    fail("bufferView " + std::to_string(a.bufferView) + " missing or out of range, expected a buffer view");
  const tinygltf::BufferView& v = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
  if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= model.buffers.size())
    fail("buffer " + std::to_string(v.buffer) + " out of range");
  const tinygltf::Buffer& buf = model.buffers[static_cast<std::size_t>(v.buffer)];
  if (v.byteOffset > buf.data.size() || v.byteLength > buf.data.size() - v.byteOffset)
    fail("buffer view " + std::to_string(a.bufferView) + " (bytes " + std::to_string(v.byteOffset) + ".." +
         std::to_string(v.byteOffset + v.byteLength) + ") exceeds its buffer of " + std::to_string(buf.data.size()) +
         " bytes");
  const int comp = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  const int ncomp = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  const int stride = a.ByteStride(v);
  if (comp <= 0 || ncomp <= 0 || stride <= 0) fail("invalid component type, type or byteStride");
  const std::size_t elem = static_cast<std::size_t>(comp) * static_cast<std::size_t>(ncomp);
  if (a.count > 0) {
    const std::size_t s = static_cast<std::size_t>(stride);
    if (a.byteOffset > v.byteLength || (a.count - 1) > (v.byteLength - a.byteOffset) / s ||
        a.byteOffset + (a.count - 1) * s + elem > v.byteLength)
      fail(std::to_string(a.count) + " elements of " + std::to_string(elem) + " bytes (stride " + std::to_string(s) +
           ", offset " + std::to_string(a.byteOffset) + ") exceed buffer view " + std::to_string(a.bufferView) +
           " of " + std::to_string(v.byteLength) + " bytes");
  }
  AccessorData d;
  d.base = buf.data.data() + v.byteOffset + a.byteOffset;
  d.stride = static_cast<std::size_t>(stride);
  d.count = a.count;
  d.component_type = a.componentType;
  return d;
}

template <class T>
T load_le(const unsigned char* p) {
  unsigned char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = host_is_little_endian() ? p[i] : p[sizeof(T) - 1 - i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;  // geometry only: images are never decoded
}

class GltfGeometry {
 public:
  GltfGeometry(const tinygltf::Model& model, const std::string& path, MeshData& out)
      : model_(model), path_(path), out_(out) {}

  void add_scene() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (static_cast<std::size_t>(s) >= model_.scenes.size())
        throw IoError(path_ + ": default scene " + std::to_string(s) + " out of range, expected 0.." +
                      std::to_string(model_.scenes.size() - 1));
      roots = model_.scenes[static_cast<std::size_t>(s)].nodes;
      if (model_.scenes.size() > 1)
        out_.warnings.push_back(path_ + ": " + std::to_string(model_.scenes.size()) + " scenes, only scene " +
                                std::to_string(s) + " read");
    } else if (!model_.nodes.empty()) {
      // No scene: every node that is nobody's child is a root.
      std::vector<char> is_child(model_.nodes.size(), 0);
      for (const auto& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && static_cast<std::size_t>(c) < is_child.size()) is_child[static_cast<std::size_t>(c)] = 1;
      for (std::size_t i = 0; i < model_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(static_cast<int>(i));
    } else {
      // No node at all: every mesh once, untransformed.
      for (std::size_t m = 0; m < model_.meshes.size(); ++m) add_mesh(static_cast<int>(m), identity());
      if (!model_.meshes.empty()) out_.warnings.push_back(path_ + ": no scene and no node: meshes read untransformed");
      return;
    }
    on_path_.assign(model_.nodes.size(), 0);
    visit_budget_ = 4 * model_.nodes.size() + 64;
    for (int r : roots) visit(r);
  }

  int skipped_primitives = 0;
  std::string skipped_modes;

 private:
  // Depth-first walk with an explicit stack (a deep hierarchy must not
  // exhaust the call stack); a node's meshes come before its children's.
  void visit(int root) {
    struct Step {
      int node;
      Mat4 parent;
      bool leave;  // leaving the node: it is no longer on the path
    };
    std::vector<Step> stack{{root, identity(), false}};
    while (!stack.empty()) {
      const Step s = stack.back();
      stack.pop_back();
      if (s.leave) {
        on_path_[static_cast<std::size_t>(s.node)] = 0;
        continue;
      }
      const int index = s.node;
      if (index < 0 || static_cast<std::size_t>(index) >= model_.nodes.size())
        throw IoError(path_ + ": node index " + std::to_string(index) + " out of range, expected 0.." +
                      std::to_string(static_cast<long long>(model_.nodes.size()) - 1));
      if (on_path_[static_cast<std::size_t>(index)])
        throw IoError(path_ + ": node " + std::to_string(index) + " is its own ancestor, expected a tree of nodes");
      if (visit_budget_-- == 0)
        throw IoError(path_ + ": node hierarchy visits nodes too many times, expected disjoint trees of nodes");
      const tinygltf::Node& n = model_.nodes[static_cast<std::size_t>(index)];
      const Mat4 m = multiply(s.parent, local_transform(n, index, path_));
      if (n.mesh >= 0) add_mesh(n.mesh, m);
      on_path_[static_cast<std::size_t>(index)] = 1;
      stack.push_back({index, m, true});
      for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, m, false});
    }
  }

  void add_mesh(int mesh_index, const Mat4& m) {
    if (static_cast<std::size_t>(mesh_index) >= model_.meshes.size())
      throw IoError(path_ + ": mesh index " + std::to_string(mesh_index) + " out of range, expected 0.." +
                    std::to_string(static_cast<long long>(model_.meshes.size()) - 1));
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
    const bool flip = det3(m) < 0;  // mirrored instance: keep the outward orientation
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(mesh.primitives[p], m, flip, path_ + ": mesh " + std::to_string(mesh_index) + " primitive " +
                                                     std::to_string(p));
  }

  void add_primitive(const tinygltf::Primitive& prim, const Mat4& m, bool flip, const std::string& where) {
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      ++skipped_primitives;
      std::string name = mode == TINYGLTF_MODE_POINTS ? "points" : (mode <= 3 ? "lines" : std::to_string(mode));
      if (skipped_modes.find(name) == std::string::npos) skipped_modes += (skipped_modes.empty() ? "" : ", ") + name;
      return;
    }
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) {
      out_.warnings.push_back(where + ": no POSITION attribute, primitive skipped");
      return;
    }
    const AccessorData pd = accessor_data(model_, pos->second, where);
    const tinygltf::Accessor& pa = model_.accessors[static_cast<std::size_t>(pos->second)];
    if (pa.type != TINYGLTF_TYPE_VEC3 || pa.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      throw IoError(where + ": POSITION accessor " + std::to_string(pos->second) +
                    " is not VEC3 of float (quantized positions are not supported), expected VEC3 float");
    if (out_.vertices.size() + pd.count > 2147483647ull) throw IoError(where + ": too many vertices");
    const std::size_t base = out_.vertices.size();
    for (std::size_t i = 0; i < pd.count; ++i) {
      const unsigned char* q = pd.base + i * pd.stride;
      Vec3 p(load_le<float>(q), load_le<float>(q + 4), load_le<float>(q + 8));
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw IoError(where + ": vertex " + std::to_string(i) + " is not finite, expected finite coordinates");
      out_.vertices.push_back(transform_point(m, p));
    }

    // Vertex ids of the primitive, then triangles by mode.
    std::vector<std::uint32_t> ids;
    if (prim.indices >= 0) {
      const AccessorData id = accessor_data(model_, prim.indices, where);
      const tinygltf::Accessor& ia = model_.accessors[static_cast<std::size_t>(prim.indices)];
      if (ia.type != TINYGLTF_TYPE_SCALAR)
        throw IoError(where + ": index accessor " + std::to_string(prim.indices) + " is not SCALAR");
      ids.resize(id.count);
      for (std::size_t i = 0; i < id.count; ++i) {
        const unsigned char* q = id.base + i * id.stride;
        switch (id.component_type) {
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: ids[i] = *q; break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: ids[i] = load_le<std::uint16_t>(q); break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: ids[i] = load_le<std::uint32_t>(q); break;
          default:
            throw IoError(where + ": index accessor " + std::to_string(prim.indices) +
                          " has component type " + std::to_string(id.component_type) +
                          ", expected unsigned byte, short or int");
        }
        if (ids[i] >= pd.count)
          throw IoError(where + ": index " + std::to_string(ids[i]) + " (entry " + std::to_string(i) +
                        ") out of range, expected 0.." + std::to_string(static_cast<long long>(pd.count) - 1));
      }
    } else {
      ids.resize(pd.count);
      for (std::size_t i = 0; i < pd.count; ++i) ids[i] = static_cast<std::uint32_t>(i);
    }
    auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      std::array<int, 3> t = {static_cast<int>(base + a), static_cast<int>(base + b), static_cast<int>(base + c)};
      if (flip) std::swap(t[1], t[2]);
      out_.triangles.push_back(t);
    };
    const std::size_t n = ids.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0)
        out_.warnings.push_back(where + ": " + std::to_string(n) + " indices is not a multiple of 3, last " +
                                std::to_string(n % 3) + " ignored");
      for (std::size_t i = 0; i + 2 < n; i += 3) add(ids[i], ids[i + 1], ids[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t i = 0; i + 2 < n; ++i)
        if (i % 2 == 0) add(ids[i], ids[i + 1], ids[i + 2]);
        else add(ids[i], ids[i + 2], ids[i + 1]);
    } else {
      for (std::size_t i = 0; i + 2 < n; ++i) add(ids[i + 1], ids[i + 2], ids[0]);
    }
  }

  const tinygltf::Model& model_;
  const std::string& path_;
  MeshData& out_;
  std::vector<char> on_path_;
  std::size_t visit_budget_ = 0;
};

// Checks the GLB container (header and chunk headers) so that errors name a
// byte offset; returns the number of bytes to hand to tinygltf.
std::size_t check_glb(ByteReader& b) {
  b.seek(4);
  const bool swap = !host_is_little_endian();
  const std::uint32_t version = b.read<std::uint32_t>("GLB version", swap);
  if (version != 2) {
    b.seek(4);
    b.fail("GLB container version " + std::to_string(version) + ", expected 2 (glTF 2.0)");
  }
  const std::uint32_t length = b.read<std::uint32_t>("GLB length", swap);
  if (length > b.size()) {
    b.seek(8);
    b.fail("truncated GLB: the header announces " + std::to_string(length) + " bytes but the file has " +
           std::to_string(b.size()) + ", expected the whole file");
  }
  if (length < 20) {
    b.seek(8);
    b.fail("GLB length " + std::to_string(length) + " too small, expected at least 20 bytes (header + JSON chunk)");
  }
  const std::uint32_t json_len = b.read<std::uint32_t>("JSON chunk length", swap);
  const std::uint32_t json_type = b.read<std::uint32_t>("JSON chunk type", swap);
  if (json_type != kChunkJson) {
    b.seek(16);
    b.fail("first chunk is not JSON, expected chunk type 0x4E4F534A ('JSON')");
  }
  if (json_len == 0 || json_len > length - 20) {
    b.seek(12);
    b.fail("JSON chunk of " + std::to_string(json_len) + " bytes runs past the end of the GLB (" +
           std::to_string(length) + " bytes), expected at most " + std::to_string(length - 20));
  }
  std::size_t next = 20 + static_cast<std::size_t>(json_len);
  if (next < length) {
    if (length - next < 8) {
      b.seek(next);
      b.fail("truncated chunk header, expected 8 bytes (length and type)");
    }
    b.seek(next);
    const std::uint32_t bin_len = b.read<std::uint32_t>("BIN chunk length", swap);
    const std::uint32_t bin_type = b.read<std::uint32_t>("BIN chunk type", swap);
    if (bin_type != kChunkBin) {
      b.seek(next + 4);
      b.fail("second chunk is not BIN, expected chunk type 0x004E4942 ('BIN')");
    }
    if (bin_len > length - next - 8) {
      b.seek(next);
      b.fail("BIN chunk of " + std::to_string(bin_len) + " bytes runs past the end of the GLB (" +
             std::to_string(length) + " bytes): truncated file?");
    }
  }
  return length;
}

// The JSON text of a .gltf, or of a checked GLB's JSON chunk.
std::string_view gltf_json(const ByteReader& b, bool is_glb) {
  if (!is_glb) return b.data();
  const auto json_length = load_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(b.data().data()) + 12);
  return std::string_view(b.data()).substr(20, json_length);
}

}  // namespace

MeshData read_gltf(const std::string& path) {
  ByteReader b = ByteReader::from_file(path);
  if (b.size() > 0xffffffffull) throw IoError(path + ": file too large for glTF (4 GB or more)");
  std::string base_dir = std::filesystem::path(path).parent_path().string();

  const bool is_glb = b.size() >= 4 && load_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(b.data().data())) == kGlbMagic;
  const std::size_t glb_length = is_glb ? check_glb(b) : 0;
  GltfBufferFiles buffer_files(path, base_dir, gltf_json(b, is_glb));
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&skip_image, nullptr);
  loader.SetFsCallbacks(buffer_files.callbacks());
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = is_glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(b.data().data()),
                                                       static_cast<unsigned int>(glb_length), base_dir)
                         : loader.LoadASCIIFromString(&model, &err, &warn, b.data().data(),
                                                      static_cast<unsigned int>(b.size()), base_dir);
  if (!ok && !buffer_files.read_failure().empty()) throw IoError(buffer_files.read_failure());
  auto trim = [](std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
      if (c == '\n') c = ';';
    return s;
  };
  if (!ok) {
    std::string what = is_glb ? "invalid glTF in the JSON chunk at byte 20: " : "invalid glTF JSON: ";
    if (err.empty()) err = "unknown error";
    throw IoError(path + ": " + what + trim(err));
  }
  MeshData data;
  data.split_vertices = true;
  if (!warn.empty()) data.warnings.push_back(path + ": " + trim(warn));
  for (const std::string& ext : model.extensionsRequired)
    if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" || ext == "KHR_mesh_quantization")
      throw IoError(path + ": required extension " + ext + " is not supported, expected uncompressed float geometry");

  GltfGeometry geometry(model, path, data);
  geometry.add_scene();
  if (geometry.skipped_primitives > 0)
    data.warnings.push_back(path + ": skipped " + std::to_string(geometry.skipped_primitives) +
                            " primitive(s) that are not triangles (" + geometry.skipped_modes + ")");
  return data;
}

void write_glb(const std::string& path, const MeshData& data) {
  const std::size_t nv = data.vertices.size();
  const std::size_t nt = data.triangles.size();
  if (nt == 0 || nv == 0) throw IoError(path + ": cannot write an empty mesh to glTF, expected at least one triangle");
  for (std::size_t t = 0; t < nt; ++t)
    for (int id : data.triangles[t])
      if (id < 0 || static_cast<std::size_t>(id) >= nv)
        throw IoError(path + ": cannot write: triangle " + std::to_string(t) + " has vertex id " +
                      std::to_string(id) + ", expected 0.." + std::to_string(nv - 1));
  if (nv * 12 + nt * 12 > 0xffffff00ull) throw IoError(path + ": cannot write: mesh too large for a GLB file");

  // BIN chunk: positions (float VEC3) then indices (uint32); both multiples of 4.
  std::string bin;
  bin.reserve(nv * 12 + nt * 12);
  auto put32 = [](std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
  };
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& p : data.vertices)
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(p[k]);
      if (!std::isfinite(f)) throw IoError(path + ": cannot write a non-finite (or float-overflowing) coordinate");
      lo[k] = std::min(lo[k], f);
      hi[k] = std::max(hi[k], f);
      std::uint32_t u;
      std::memcpy(&u, &f, 4);
      put32(bin, u);
    }
  for (const auto& t : data.triangles)
    for (int id : t) put32(bin, static_cast<std::uint32_t>(id));

  auto num = [](float f) { return format_double(static_cast<double>(f)); };
  const std::string pos_bytes = std::to_string(nv * 12);
  const std::string idx_bytes = std::to_string(nt * 12);
  std::string json;
  json += R"({"asset":{"version":"2.0","generator":"anisurf"},"scene":0,"scenes":[{"nodes":[0]}],)";
  json += R"("nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4}]}],)";
  json += R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" + std::to_string(nv) +
          R"(,"type":"VEC3","min":[)" + num(lo[0]) + "," + num(lo[1]) + "," + num(lo[2]) + R"(],"max":[)" +
          num(hi[0]) + "," + num(hi[1]) + "," + num(hi[2]) + "]},";
  json += R"({"bufferView":1,"componentType":5125,"count":)" + std::to_string(3 * nt) + R"(,"type":"SCALAR"}],)";
  json += R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" + pos_bytes + R"(,"target":34962},)";
  json += R"({"buffer":0,"byteOffset":)" + pos_bytes + R"(,"byteLength":)" + idx_bytes + R"(,"target":34963}],)";
  json += R"("buffers":[{"byteLength":)" + std::to_string(bin.size()) + "}]}";
  while (json.size() % 4 != 0) json += ' ';

  std::string out;
  out.reserve(28 + json.size() + bin.size());
  put32(out, kGlbMagic);
  put32(out, 2);
  put32(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put32(out, static_cast<std::uint32_t>(json.size()));
  put32(out, kChunkJson);
  out += json;
  put32(out, static_cast<std::uint32_t>(bin.size()));
  put32(out, kChunkBin);
  out += bin;
  AtomicFile file(path);
  file.stream().write(out.data(), static_cast<std::streamsize>(out.size()));
  file.commit();
}

}  // namespace anisurf::io
