#include "io/vtk_xml_encoding.h"

#include <zlib.h>

#include <cstring>

#include "core/error.h"

namespace anisurf::io {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

void put_uint(std::string& out, std::uint64_t v, int bytes) {
  if (bytes == 4) {
    const auto v32 = static_cast<std::uint32_t>(v);
    out.append(reinterpret_cast<const char*>(&v32), 4);
  } else {
    out.append(reinterpret_cast<const char*>(&v), 8);
  }
}

}  // namespace

std::string base64_encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (b[i] << 16) | (b[i + 1] << 8) | b[i + 2];
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    const std::uint32_t v = (b[i] << 16) | (rest == 2 ? b[i + 1] << 8 : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

bool Base64Decoder::decode_group(std::string& out) {
  char g[4];
  int n = 0;
  while (n < 4) {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    if (pos_ >= text_.size()) return false;
    g[n++] = text_[pos_++];
  }
  int v[4];
  int pad = 0;
  for (int k = 0; k < 4; ++k) {
    if (g[k] == '=' && k >= 2) {
      v[k] = 0;
      ++pad;
    } else {
      if (pad > 0) return false;  // data after padding inside a group
      v[k] = base64_value(g[k]);
      if (v[k] < 0) return false;
    }
  }
  const std::uint32_t bits = (static_cast<std::uint32_t>(v[0]) << 18) | (static_cast<std::uint32_t>(v[1]) << 12) |
                             (static_cast<std::uint32_t>(v[2]) << 6) | static_cast<std::uint32_t>(v[3]);
  out += static_cast<char>((bits >> 16) & 255);
  if (pad < 2) out += static_cast<char>((bits >> 8) & 255);
  if (pad < 1) out += static_cast<char>(bits & 255);
  return true;
}

bool Base64Decoder::decode_until(std::size_t n, std::string& out) {
  while (out.size() < n)
    if (!decode_group(out)) return false;
  return true;
}

bool Base64Decoder::decode_all(std::string& out) {
  for (;;) {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    if (pos_ >= text_.size()) return true;
    if (!decode_group(out)) return false;
  }
}

CompressedArray zlib_compress_blocks(std::string_view bytes, std::size_t block_size, int header_bytes) {
  CompressedArray out;
  const std::size_t n_blocks = (bytes.size() + block_size - 1) / block_size;
  std::string sizes;
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::string_view block = bytes.substr(b * block_size, block_size);
    uLongf size = compressBound(static_cast<uLong>(block.size()));
    std::string buffer(size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(buffer.data()), &size, reinterpret_cast<const Bytef*>(block.data()),
                  static_cast<uLong>(block.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
      throw IoError("zlib compression failed");
    out.data.append(buffer.data(), size);
    put_uint(sizes, size, header_bytes);
  }
  put_uint(out.header, n_blocks, header_bytes);
  put_uint(out.header, block_size, header_bytes);
  put_uint(out.header, bytes.size() % block_size, header_bytes);
  out.header += sizes;
  return out;
}

bool zlib_inflate_block(std::string_view block, std::size_t size, std::string& out) {
  const std::size_t start = out.size();
  out.resize(start + size);
  uLongf got = static_cast<uLongf>(size);
  const int rc = uncompress(reinterpret_cast<Bytef*>(out.data() + start), &got,
                            reinterpret_cast<const Bytef*>(block.data()), static_cast<uLong>(block.size()));
  if (rc != Z_OK || got != size) {
    out.resize(start);
    return false;
  }
  return true;
}

}  // namespace anisurf::io
