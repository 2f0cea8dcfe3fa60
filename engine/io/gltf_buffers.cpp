// External buffer files of a glTF asset: checked before tinygltf runs, then
// read through tinygltf's file callbacks (see gltf_buffers.h for the rules).
#include "io/gltf_buffers.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace anisurf::io {
namespace {

namespace fs = std::filesystem;

// Padding a writer may add after a buffer's bytes (to a multiple of 4).
constexpr std::uint64_t kMaxPadding = 3;

// Percent-decoding as tinygltf applies it to URIs ('+' is a space, %XY a byte;
// invalid hex digits count as 0), so that the checked path is the one
// tinygltf asks for.
unsigned char hex_digit(unsigned char c) {
  if (c >= '0' && c <= '9') return static_cast<unsigned char>(c - '0');
  if (c >= 'a' && c <= 'f') return static_cast<unsigned char>(c - 'a' + 10);
  if (c >= 'A' && c <= 'F') return static_cast<unsigned char>(c - 'A' + 10);
  return 0;
}

std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      const auto hi = hex_digit(static_cast<unsigned char>(uri[i + 1]));
      const auto lo = hex_digit(static_cast<unsigned char>(uri[i + 2]));
      out += static_cast<char>((hi << 4) | lo);
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The scheme of an absolute URI ("http" in "http://..."), or "".
std::string uri_scheme(const std::string& uri) {
  const std::size_t colon = uri.find(':');
  if (colon == std::string::npos || colon == 0) return "";
  for (std::size_t i = 0; i < colon; ++i) {
    const char c = uri[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
    if (!letter && (i == 0 || !((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.'))) return "";
  }
  return uri.substr(0, colon);
}

// The path tinygltf asks the callbacks for: the base directory joined with
// the decoded URI, in a form that compares equal for equal paths.
std::string normal_path(const std::string& path) { return fs::path(path).lexically_normal().string(); }

std::string joined(const std::string& base_dir, const std::string& relative) {
  if (base_dir.empty()) return relative;
  return base_dir.back() == '/' ? base_dir + relative : base_dir + "/" + relative;
}

const char* file_type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

void check_file_type(const struct stat& st, const std::string& where) {
  if (!S_ISREG(st.st_mode))
    throw IoError(where + ": is " + file_type_name(st.st_mode) + ", expected a regular file");
}

void check_file_size(std::uint64_t size, std::uint64_t byte_length, const std::string& where) {
  if (size < byte_length)
    throw IoError(where + ": the file holds " + std::to_string(size) + " bytes, expected the buffer's byteLength " +
                  std::to_string(byte_length));
  if (size - byte_length > kMaxPadding)
    throw IoError(where + ": the file holds " + std::to_string(size) + " bytes, expected the buffer's byteLength " +
                  std::to_string(byte_length) + " (at most " + std::to_string(kMaxPadding) + " bytes more)");
}

// The first byte_length bytes of a regular file, opened without blocking
// and checked again on the open descriptor (the file may have changed since
// it was checked by name).
std::vector<unsigned char> read_buffer_bytes(const std::string& path, std::uint64_t byte_length,
                                             const std::string& where) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw IoError(where + ": cannot open (" + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw IoError(where + ": cannot stat (" + std::strerror(errno) + ")");
  check_file_type(st, where);
  check_file_size(static_cast<std::uint64_t>(st.st_size), byte_length, where);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(byte_length));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(where + ": read error (" + std::strerror(errno) + ")");
    if (n == 0)
      throw IoError(where + ": the file ended after " + std::to_string(done) + " bytes, expected " +
                    std::to_string(byte_length));
    done += static_cast<std::size_t>(n);
  }
  return bytes;
}

}  // namespace

GltfBufferFiles::GltfBufferFiles(const std::string& gltf_path, const std::string& base_dir, std::string_view json)
    : gltf_path_(gltf_path), base_dir_(base_dir) {
  const nlohmann::json doc = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return;
  const auto buffers = doc.find("buffers");
  if (buffers == doc.end() || !buffers->is_array()) return;
  for (std::size_t i = 0; i < buffers->size(); ++i) {
    const nlohmann::json& b = (*buffers)[i];
    if (!b.is_object()) continue;
    const auto uri = b.find("uri");
    const auto length = b.find("byteLength");
    if (uri == b.end() || !uri->is_string() || length == b.end() || !length->is_number_unsigned()) continue;
    check_buffer(static_cast<int>(i), uri->get<std::string>(), length->get<std::uint64_t>());
  }
}

void GltfBufferFiles::check_buffer(int index, const std::string& uri, std::uint64_t byte_length) {
  if (uri.rfind("data:", 0) == 0) return;  // embedded: decoded by tinygltf
  const std::string where = gltf_path_ + ": buffer " + std::to_string(index) + " uri '" + uri + "'";
  if (const std::string scheme = uri_scheme(uri); !scheme.empty())
    throw IoError(where + ": URI scheme '" + scheme +
                  ":' is not supported, expected a data: URI or a path relative to the .gltf's directory");
  const std::string decoded = percent_decoded(uri);
  if (decoded.find('\0') != std::string::npos)
    throw IoError(where + ": the path holds a NUL byte, expected a file name");
  const fs::path relative = fs::path(decoded).lexically_normal();
  if (relative.has_root_directory() || relative.has_root_name())
    throw IoError(where + ": absolute path, expected a path relative to the .gltf's directory");
  if (!relative.empty() && *relative.begin() == "..")
    throw IoError(where + ": the path leaves the .gltf's directory, expected a file under it");
  const std::string path = joined(base_dir_, decoded);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw IoError(where + ": cannot open " + path + " (" + std::strerror(errno) + ")");
  check_file_type(st, where);
  std::error_code ec_dir, ec_file;
  const fs::path dir = fs::canonical(base_dir_.empty() ? fs::path(".") : fs::path(base_dir_), ec_dir);
  const fs::path file = fs::canonical(path, ec_file);
  if (ec_dir || ec_file) throw IoError(where + ": cannot resolve " + path + " (" + (ec_dir ? ec_dir : ec_file).message() + ")");
  const fs::path inside = file.lexically_relative(dir);
  if (inside.empty() || *inside.begin() == "..")
    throw IoError(where + ": resolves through a symbolic link to " + file.string() +
                  ", outside the .gltf's directory, expected a file under it");
  if (byte_length == 0) throw IoError(where + ": byteLength 0, expected at least 1 byte");
  check_file_size(static_cast<std::uint64_t>(st.st_size), byte_length, where);
  allowed_[normal_path(path)] = Allowed{where, byte_length};
}

tinygltf::FsCallbacks GltfBufferFiles::callbacks() {
  tinygltf::FsCallbacks c{};
  c.FileExists = &GltfBufferFiles::exists;
  c.ExpandFilePath = &GltfBufferFiles::expand;
  c.ReadWholeFile = &GltfBufferFiles::read;
  c.WriteWholeFile = &GltfBufferFiles::refuse_write;
  c.user_data = this;
  return c;
}

bool GltfBufferFiles::exists(const std::string& path, void* self) {
  return static_cast<GltfBufferFiles*>(self)->allowed_.count(normal_path(path)) > 0;
}

std::string GltfBufferFiles::expand(const std::string& path, void*) { return path; }

bool GltfBufferFiles::read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self) {
  auto& files = *static_cast<GltfBufferFiles*>(self);
  const auto it = files.allowed_.find(normal_path(path));
  if (it == files.allowed_.end()) {
    if (err) *err += "not a checked buffer file";
    return false;
  }
  try {
    *out = read_buffer_bytes(path, it->second.byte_length, it->second.where);
    return true;
  } catch (const IoError& e) {
    files.read_failure_ = e.what();
    if (err) *err += e.what();
    return false;
  }
}

bool GltfBufferFiles::refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "anisurf never writes through tinygltf";
  return false;
}

}  // namespace anisurf::io
