// Tokenizer shared by the text readers: whole file in memory, whitespace
// separated tokens, comment lines, line numbers for error messages.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace anisurf {

class TextReader {
 public:
  // Reads the whole file; throws IoError if it cannot be opened.
  explicit TextReader(const std::string& path, char comment = '#');
  // Reads from a buffer (tests); `path` only names it in messages.
  TextReader(std::string contents, const std::string& path, char comment);

  // Next whitespace-separated token; false at end of file. Comments run from
  // the comment character to the end of the line.
  bool next(std::string_view& token);
  // Next token; fails with "expected <what>" at end of file.
  std::string_view token(const char* what);
  // Peeks the next token without consuming it (empty at end).
  std::string_view peek();
  double read_double(const char* what);
  // Finite doubles only: NaN / infinity fail with a message naming `what`.
  double read_finite(const char* what);
  long long read_int(const char* what);
  // Integer in [lo, hi].
  long long read_int(const char* what, long long lo, long long hi);
  // The rest of the current line (without the newline), advancing past it.
  std::string_view rest_of_line();
  // Line-bounded reading (OBJ, OFF, PLY ascii): the next token on the current
  // line; false (consuming nothing) at the end of the line or of the file.
  // A comment ends the line. Use rest_of_line() to move to the next line.
  bool next_on_line(std::string_view& token);
  // Parses an already-read token (fails like read_double / read_int, naming
  // `what` and the line of the last token).
  double parse_double(std::string_view token, const char* what) const;
  long long parse_int(std::string_view token, const char* what) const;
  bool at_end();
  // Line of the last token returned (1-based).
  int line() const { return token_line_; }
  // The whole text and the reading position, for a caller that parses a
  // run of whole lines itself; skip_parsed(end, lines) then moves past them
  // (`end` just after their last newline, `lines` the newlines passed).
  std::string_view text() const { return data_; }
  char comment() const { return comment_; }
  std::size_t position() const { return pos_; }
  void skip_parsed(std::size_t end, int lines) {
    pos_ = end;
    line_ += lines;
  }
  const std::string& path() const { return path_; }
  // Throws IoError "path:line: <message>".
  [[noreturn]] void fail(const std::string& message) const;
  // Throws IoError "path:line: expected <what>, found '<token>'".
  [[noreturn]] void fail_expected(const char* what, std::string_view found) const;

 private:
  void skip_space_and_comments();
  // What each byte is to the tokenizer (the comment character's entry
  // depends on the reader).
  enum : std::uint8_t { kToken, kSpace, kNewline, kComment };
  void classify_characters();
  std::array<std::uint8_t, 256> kind_{};
  std::string data_;
  std::string path_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
  char comment_;
};

// Reader of binary data with byte offsets in error messages.
class ByteReader {
 public:
  ByteReader(std::string data, std::string path) : data_(std::move(data)), path_(std::move(path)) {}
  static ByteReader from_file(const std::string& path);
  std::size_t size() const { return data_.size(); }
  std::size_t offset() const { return pos_; }
  void seek(std::size_t p) { pos_ = p; }
  bool at_end() const { return pos_ >= data_.size(); }
  // Reads n raw bytes; fails "truncated at byte X, expected <what>".
  const char* bytes(std::size_t n, const char* what);
  template <class T>
  T read(const char* what, bool swap = false) {
    T v;
    const char* p = bytes(sizeof(T), what);
    char* out = reinterpret_cast<char*>(&v);
    for (std::size_t i = 0; i < sizeof(T); ++i) out[i] = swap ? p[sizeof(T) - 1 - i] : p[i];
    return v;
  }
  const std::string& data() const { return data_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& message) const;  // "path: byte X: message"

 private:
  std::string data_;
  std::string path_;
  std::size_t pos_ = 0;
};

// Parses a whole token as a number: false if it is not one. Doubles also accept
// Fortran exponents (1.0D+00) and values outside the normal range (denormals,
// overflow to infinity), as strtod reads them.
bool parse_real(std::string_view token, double& value);
bool parse_integer(std::string_view token, long long& value);
// The token in quotes for messages, cut to 40 characters.
std::string quoted(std::string_view token);

// Reads a whole file into a string; throws IoError naming the path (a
// directory is refused by name).
std::string read_file_contents(const std::string& path);
// Shortest decimal text that reads back to exactly the same double.
std::string format_double(double v);
// The same text appended to `out` (no string of its own: the writers'
// inner loops).
void append_double(std::string& out, double v);
bool host_is_little_endian();

}  // namespace anisurf
