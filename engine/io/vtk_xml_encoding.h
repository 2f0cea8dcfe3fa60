// Encodings of VTK XML data arrays: base64 and the zlib-compressed block
// layout of vtkZLibDataCompressor (header: number of blocks, block size, size
// of the last block or 0 when it is full, compressed size of each block).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace anisurf::io {

// Base64 text of `bytes` (with '=' padding).
std::string base64_encode(std::string_view bytes);

// Decoder of base64 text that may be the concatenation of separately padded
// parts (VTK writes a header and data either as one stream or as two).
class Base64Decoder {
 public:
  explicit Base64Decoder(std::string_view text) : text_(text) {}
  // Decodes groups of 4 characters (whitespace skipped) until `out` holds at
  // least `n` bytes; false on a character outside base64 or a text too short.
  bool decode_until(std::size_t n, std::string& out);
  // Decodes everything left; false on a character outside base64.
  bool decode_all(std::string& out);
  // Characters consumed so far.
  std::size_t consumed() const { return pos_; }

 private:
  bool decode_group(std::string& out);
  std::string_view text_;
  std::size_t pos_ = 0;
};

// zlib blocks of `bytes` (`block_size` bytes each) with the header, whose
// integers are UInt32 or UInt64 (`header_bytes` 4 or 8), as written.
struct CompressedArray {
  std::string header;
  std::string data;
};
CompressedArray zlib_compress_blocks(std::string_view bytes, std::size_t block_size, int header_bytes);
// Inflates one zlib block into exactly `size` bytes appended to `out`; false
// if the block is corrupt or inflates to another size.
bool zlib_inflate_block(std::string_view block, std::size_t size, std::string& out);

}  // namespace anisurf::io
