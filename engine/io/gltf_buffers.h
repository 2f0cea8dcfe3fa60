// External buffer files of a glTF asset (internal to engine/io/gltf.cpp).
// A buffer URI that is not a data: URI must name a regular file under the
// .gltf's directory: absolute paths, URI schemes, paths leaving the directory
// (by "..", or through a symbolic link) are refused, and so are FIFOs,
// directories and devices (checked with stat before opening; opened without
// blocking). The file holds the buffer's byteLength bytes (up to 3 bytes of
// padding more): its size is checked before reading, and only byteLength
// bytes are read. Image files are never read.
#pragma once
#include <tiny_gltf.h>

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace anisurf::io {

class GltfBufferFiles {
 public:
  // Checks the buffer URIs of `json` (the asset's JSON text) against the rules
  // above; throws IoError naming `gltf_path`, the buffer and its URI. JSON
  // that does not parse is left to tinygltf to report.
  GltfBufferFiles(const std::string& gltf_path, const std::string& base_dir, std::string_view json);

  // File callbacks for tinygltf that open only the checked buffer files.
  tinygltf::FsCallbacks callbacks();
  // Why a checked file could not be read after all (it changed meanwhile), or "".
  const std::string& read_failure() const { return read_failure_; }

 private:
  struct Allowed {
    std::string where;  // "PATH: buffer N uri 'URI'" for messages
    std::uint64_t byte_length = 0;
  };
  static bool exists(const std::string& path, void* self);
  static std::string expand(const std::string& path, void* self);
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self);
  static bool refuse_write(std::string* err, const std::string& path, const std::vector<unsigned char>&, void*);

  void check_buffer(int index, const std::string& uri, std::uint64_t byte_length);

  std::string gltf_path_, base_dir_;
  std::map<std::string, Allowed> allowed_;  // lexically normal path -> buffer
  std::string read_failure_;
};

}  // namespace anisurf::io
