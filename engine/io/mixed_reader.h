// Reader of files that mix text and binary data (Gmsh .msh binary, legacy VTK
// BINARY): whitespace separated tokens and raw values from one cursor. Error
// messages name the file and the line (text mode) or the byte offset (binary
// mode, set by the caller for files whose data is binary).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace anisurf {

class MixedReader {
 public:
  MixedReader(std::string data, std::string path) : data_(std::move(data)), path_(std::move(path)) {}

  // Binary mode: errors give the byte offset instead of the line.
  void set_binary(bool binary) { binary_ = binary; }
  bool binary() const { return binary_; }
  std::size_t size() const { return data_.size(); }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }
  // True when only whitespace is left.
  bool at_end();

  // Next whitespace-separated token; fails "unexpected end of file, expected
  // <what>" at the end.
  std::string_view token(const char* what);
  // The next token without consuming it (empty at the end).
  std::string_view peek();
  // Token parsed as an integer in [lo, hi] / as a double.
  long long read_int(const char* what, long long lo, long long hi);
  double read_double(const char* what);
  // Consumes the next token and fails unless it is `expected`.
  void expect(std::string_view expected);
  // The rest of the current line without its end, moving past the newline.
  std::string_view rest_of_line();
  // Moves past the end of the current line (before binary data that follows a
  // text line).
  void skip_line_end();
  // Skips blanks and newlines (after binary data, before a text keyword).
  void skip_space();
  // Moves just past the next occurrence of `marker`; false (not moving) if
  // there is none.
  bool skip_past(std::string_view marker);

  // n raw bytes; fails "truncated file, expected <what>".
  const char* bytes(std::size_t n, const char* what);
  // A binary value, byte-swapped when `swap`.
  template <class T>
  T read(const char* what, bool swap) {
    T v;
    const char* p = bytes(sizeof(T), what);
    char* out = reinterpret_cast<char*>(&v);
    for (std::size_t i = 0; i < sizeof(T); ++i) out[i] = swap ? p[sizeof(T) - 1 - i] : p[i];
    return v;
  }
  // Fails unless `count` items of at least `min_bytes` each fit in the rest of
  // the file (a lying count is refused before anything is allocated).
  void check_fits(long long count, std::size_t min_bytes, const char* what);

  const std::string& path() const { return path_; }
  // Throws IoError "path:LINE: message" (text) or "path: byte N: message".
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_expected(const char* what, std::string_view found) const;

 private:
  int line_at(std::size_t offset) const;
  std::string data_;
  std::string path_;
  std::size_t pos_ = 0;
  std::size_t token_start_ = 0;  // where the last token (or value) began
  bool binary_ = false;
};

}  // namespace anisurf
