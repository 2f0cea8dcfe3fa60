// glTF buffer URIs: only regular files under the .gltf's directory, of the
// buffer's byteLength (checked before reading); FIFOs, directories and devices
// refused without blocking, absolute paths, URI schemes and paths leaving the
// directory refused; each message names the .gltf and the URI. data: URIs
// keep working, for .gltf and .glb alike.
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "io/mesh_io.h"
#include "test_util.h"

using namespace anisurf;
namespace fs = std::filesystem;

namespace {

// The 36 bytes of one triangle's positions (3 x VEC3 float, little endian).
std::string triangle_bytes() {
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string bytes(sizeof xyz, '\0');
  std::memcpy(bytes.data(), xyz, sizeof xyz);
  return bytes;
}

// glTF JSON of one unindexed triangle read from buffer 0 at `uri`.
std::string triangle_json(const std::string& uri, std::size_t byte_length = 36) {
  return R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
         R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":)" +
         std::to_string(byte_length) + R"(,"uri":")" + uri + R"("}]})";
}

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

fs::path write_gltf(const fs::path& dir, const std::string& uri, std::size_t byte_length = 36) {
  const fs::path gltf = dir / "scene.gltf";
  write_file(gltf, triangle_json(uri, byte_length));
  return gltf;
}

// A GLB with only a JSON chunk (its buffer is external).
fs::path write_glb(const fs::path& dir, const std::string& uri) {
  std::string json = triangle_json(uri);
  while (json.size() % 4 != 0) json += ' ';
  auto u32 = [](std::uint32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i) s[static_cast<std::size_t>(i)] = static_cast<char>((v >> (8 * i)) & 0xff);
    return s;
  };
  const fs::path glb = dir / "scene.glb";
  write_file(glb, "glTF" + u32(2) + u32(static_cast<std::uint32_t>(20 + json.size())) +
                      u32(static_cast<std::uint32_t>(json.size())) + "JSON" + json);
  return glb;
}

// The message of the IoError reading `path` throws ("" if it reads).
std::string refusal(const fs::path& path) {
  try {
    read_mesh_data(path.string());
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("glTF buffers: a regular file of the declared size is read, padding allowed") {
  const fs::path dir = test::temp_dir("gltf_buffer_regular");
  write_file(dir / "tri.bin", triangle_bytes());
  const MeshData d = read_mesh_data(write_gltf(dir, "tri.bin").string());
  CHECK(d.vertices.size() == 3);
  CHECK(d.triangles.size() == 1);
  write_file(dir / "padded.bin", triangle_bytes() + std::string(3, '\0'));
  CHECK(read_mesh_data(write_gltf(dir, "padded.bin").string()).triangles.size() == 1);
  fs::create_directories(dir / "sub");
  write_file(dir / "sub" / "tri copy.bin", triangle_bytes());
  CHECK(read_mesh_data(write_gltf(dir, "sub/tri%20copy.bin").string()).triangles.size() == 1);
  CHECK(read_mesh_data(write_glb(dir, "tri.bin").string()).triangles.size() == 1);
}

TEST_CASE("glTF buffers: data: URIs keep working") {
  const fs::path dir = test::temp_dir("gltf_buffer_data_uri");
  // base64 of triangle_bytes()
  const std::string uri = "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
  CHECK(read_mesh_data(write_gltf(dir, uri).string()).triangles.size() == 1);
  CHECK(read_mesh_data(write_glb(dir, uri).string()).triangles.size() == 1);
}

TEST_CASE("glTF buffers: a FIFO is refused without blocking") {
  const fs::path dir = test::temp_dir("gltf_buffer_fifo");
  REQUIRE(::mkfifo((dir / "pipe.bin").c_str(), 0600) == 0);
  for (const fs::path& file : {write_gltf(dir, "pipe.bin"), write_glb(dir, "pipe.bin")}) {
    const std::string msg = refusal(file);
    CAPTURE(msg);
    CHECK(contains(msg, file.string()));
    CHECK(contains(msg, "'pipe.bin'"));
    CHECK(contains(msg, "FIFO"));
  }
}

TEST_CASE("glTF buffers: directories and devices are refused") {
  const fs::path dir = test::temp_dir("gltf_buffer_not_regular");
  fs::create_directories(dir / "folder.bin");
  std::string msg = refusal(write_gltf(dir, "folder.bin"));
  CAPTURE(msg);
  CHECK(contains(msg, (dir / "scene.gltf").string()));
  CHECK(contains(msg, "'folder.bin'"));
  CHECK(contains(msg, "directory"));
  fs::create_symlink("/dev/zero", dir / "zero.bin");
  msg = refusal(write_gltf(dir, "zero.bin"));
  CHECK(contains(msg, "'zero.bin'"));
  CHECK(contains(msg, "character device"));
}

TEST_CASE("glTF buffers: a file larger than the byteLength allows is refused before reading") {
  const fs::path dir = test::temp_dir("gltf_buffer_huge");
  // 1 GB, sparse: refused from its size alone.
  write_file(dir / "huge.bin", "");
  REQUIRE(::truncate((dir / "huge.bin").c_str(), 1LL << 30) == 0);
  std::string msg = refusal(write_gltf(dir, "huge.bin"));
  CAPTURE(msg);
  CHECK(contains(msg, (dir / "scene.gltf").string()));
  CHECK(contains(msg, "'huge.bin'"));
  CHECK(contains(msg, "1073741824 bytes"));
  CHECK(contains(msg, "byteLength 36"));
  // More than 3 bytes of padding, and too short.
  write_file(dir / "long.bin", triangle_bytes() + std::string(4, '\0'));
  CHECK(contains(refusal(write_gltf(dir, "long.bin")), "40 bytes"));
  write_file(dir / "short.bin", triangle_bytes().substr(0, 24));
  msg = refusal(write_gltf(dir, "short.bin"));
  CHECK(contains(msg, "24 bytes"));
  CHECK(contains(msg, "'short.bin'"));
  // A byteLength far beyond the file is refused the same way (nothing allocated).
  write_file(dir / "tri.bin", triangle_bytes());
  CHECK(contains(refusal(write_gltf(dir, "tri.bin", 1ull << 40)), "byteLength 1099511627776"));
}

TEST_CASE("glTF buffers: absolute paths, URI schemes and paths leaving the directory are refused") {
  const fs::path root = test::temp_dir("gltf_buffer_escape");
  const fs::path dir = root / "model";
  fs::create_directories(dir / "sub");
  write_file(root / "outside.bin", triangle_bytes());
  const std::string absolute = (root / "outside.bin").string();
  struct Case {
    std::string uri, expected;
  };
  const Case cases[] = {
      {absolute, "absolute path"},
      {"../outside.bin", "leaves the .gltf's directory"},
      {"sub/../../outside.bin", "leaves the .gltf's directory"},
      {"%2E%2E/outside.bin", "leaves the .gltf's directory"},
      {"file://" + absolute, "URI scheme 'file:'"},
      {"http://example.com/outside.bin", "URI scheme 'http:'"},
  };
  for (const Case& c : cases) {
    for (const fs::path& file : {write_gltf(dir, c.uri), write_glb(dir, c.uri)}) {
      const std::string msg = refusal(file);
      CAPTURE(c.uri);
      CAPTURE(msg);
      CHECK(contains(msg, file.string()));
      CHECK(contains(msg, "'" + c.uri + "'"));
      CHECK(contains(msg, c.expected));
    }
  }
  // A symbolic link under the directory to a file outside it.
  fs::create_symlink(root / "outside.bin", dir / "link.bin");
  const std::string msg = refusal(write_gltf(dir, "link.bin"));
  CAPTURE(msg);
  CHECK(contains(msg, "'link.bin'"));
  CHECK(contains(msg, "outside the .gltf's directory"));
}

TEST_CASE("glTF buffers: a missing file names the .gltf and the URI") {
  const fs::path dir = test::temp_dir("gltf_buffer_missing");
  const std::string msg = refusal(write_gltf(dir, "absent.bin"));
  CAPTURE(msg);
  CHECK(contains(msg, (dir / "scene.gltf").string()));
  CHECK(contains(msg, "'absent.bin'"));
}
