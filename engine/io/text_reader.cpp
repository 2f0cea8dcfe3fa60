#include "io/text_reader.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/huge_pages.h"

namespace anisurf {

std::string read_file_contents(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw IoError(path + ": cannot open file (" + std::strerror(errno) + ")");
  // One read into a buffer of the file's size (a stream copy through a
  // stringstream moved every byte three times: 12% of loading a 500k-triangle
  // mesh); then chunks until the end (a pipe, or a file that grew).
  std::string text;
  const auto size = std::filesystem::file_size(path, ec);
  std::size_t used = 0;
  if (!ec && size > 0) {
    // Huge pages for a large file: one page fault per 2 MB while it is read.
    text.reserve(static_cast<std::size_t>(size));
    advise_huge_pages(text.data(), text.capacity());
    text.resize(static_cast<std::size_t>(size));
    used = std::fread(text.data(), 1, text.size(), f);
  }
  char chunk[1 << 16];
  while (!std::ferror(f) && !std::feof(f)) {
    const std::size_t n = std::fread(chunk, 1, sizeof chunk, f);
    if (n == 0) break;
    if (used + n > text.size()) text.resize(std::max(used + n, 2 * text.size()));
    std::memcpy(text.data() + used, chunk, n);
    used += n;
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IoError(path + ": read error");
  text.resize(used);
  return text;
}

std::string format_double(double v) {
  std::string out;
  append_double(out, v);
  return out;
}

void append_double(std::string& out, double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

bool parse_real(std::string_view t, double& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') ++b;
  auto r = std::from_chars(b, e, v);
  if (r.ec == std::errc() && r.ptr == e) return true;
  // from_chars refuses denormals and overflow, and Fortran exponents (1.0D+00,
  // found in some Medit files): strtod reads them all.
  std::string s(t);
  for (char& c : s)
    if (c == 'd' || c == 'D') c = 'e';
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

bool parse_integer(std::string_view t, long long& v) {
  if (t.empty()) return false;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') ++b;
  // Ids and counts: up to 18 digits cannot overflow; the rest (signs,
  // longer numbers, junk) goes to from_chars.
  if (b < e && e - b <= 18) {
    long long x = 0;
    const char* p = b;
    for (; p < e; ++p) {
      const auto digit = static_cast<unsigned>(*p - '0');
      if (digit > 9) break;
      x = 10 * x + digit;
    }
    if (p == e) {
      v = x;
      return true;
    }
  }
  auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

std::string quoted(std::string_view t) {
  std::string s(1, '\'');
  s.append(t.substr(0, 40));
  s.push_back('\'');
  return s;
}

bool host_is_little_endian() {
  const std::uint16_t x = 1;
  return *reinterpret_cast<const std::uint8_t*>(&x) == 1;
}

TextReader::TextReader(const std::string& path, char comment)
    : data_(read_file_contents(path)), path_(path), comment_(comment) {
  classify_characters();
}

TextReader::TextReader(std::string contents, const std::string& path, char comment)
    : data_(std::move(contents)), path_(path), comment_(comment) {
  classify_characters();
}

void TextReader::classify_characters() {
  kind_.fill(kToken);
  for (char c : {' ', '\t', '\r', '\f', '\v'}) kind_[static_cast<unsigned char>(c)] = kSpace;
  kind_[static_cast<unsigned char>('\n')] = kNewline;
  if (comment_) kind_[static_cast<unsigned char>(comment_)] = kComment;
}

void TextReader::skip_space_and_comments() {
  const std::size_t n = data_.size();
  const char* d = data_.data();
  while (pos_ < n) {
    const auto c = static_cast<unsigned char>(d[pos_]);
    const std::uint8_t k = kind_[c];
    if (k == kToken) break;
    if (k == kNewline) {
      ++line_;
      ++pos_;
    } else if (k == kSpace) {
      ++pos_;
    } else {  // a comment, to the end of the line
      while (pos_ < n && d[pos_] != '\n') ++pos_;
    }
  }
}

bool TextReader::next(std::string_view& token) {
  skip_space_and_comments();
  if (pos_ >= data_.size()) {
    token_line_ = line_;
    return false;
  }
  const std::size_t start = pos_, n = data_.size();
  const char* d = data_.data();
  while (pos_ < n && kind_[static_cast<unsigned char>(d[pos_])] == kToken) ++pos_;
  token_line_ = line_;
  token = std::string_view(d + start, pos_ - start);
  return true;
}

std::string_view TextReader::token(const char* what) {
  std::string_view t;
  if (!next(t)) fail(std::string("unexpected end of file, expected ") + what);
  return t;
}

std::string_view TextReader::peek() {
  std::size_t p = pos_;
  int l = line_, tl = token_line_;
  std::string_view t;
  if (!next(t)) t = {};
  pos_ = p;
  line_ = l;
  token_line_ = tl;
  return t;
}

bool TextReader::at_end() {
  skip_space_and_comments();
  return pos_ >= data_.size();
}

double TextReader::read_double(const char* what) { return parse_double(token(what), what); }

double TextReader::parse_double(std::string_view t, const char* what) const {
  double v = 0;
  if (!parse_real(t, v)) fail_expected(what, t);
  return v;
}

double TextReader::read_finite(const char* what) {
  double v = read_double(what);
  if (!std::isfinite(v)) fail(std::string(what) + " is not a finite number ('" + std::to_string(v) + "')");
  return v;
}

long long TextReader::read_int(const char* what) { return parse_int(token(what), what); }

long long TextReader::parse_int(std::string_view t, const char* what) const {
  long long v = 0;
  if (!parse_integer(t, v)) fail_expected(what, t);
  return v;
}

long long TextReader::read_int(const char* what, long long lo, long long hi) {
  long long v = read_int(what);
  if (v < lo || v > hi)
    fail(std::string(what) + " " + std::to_string(v) + " out of range, expected " + std::to_string(lo) + ".." +
         std::to_string(hi));
  return v;
}

std::string_view TextReader::rest_of_line() {
  const std::size_t n = data_.size();
  while (pos_ < n && (data_[pos_] == ' ' || data_[pos_] == '\t')) ++pos_;
  std::size_t start = pos_;
  while (pos_ < n && data_[pos_] != '\n') ++pos_;
  std::size_t end = pos_;
  if (end > start && data_[end - 1] == '\r') --end;
  token_line_ = line_;
  if (pos_ < n) {
    ++pos_;
    ++line_;
  }
  return std::string_view(data_).substr(start, end - start);
}

bool TextReader::next_on_line(std::string_view& token) {
  const std::size_t n = data_.size();
  const char* d = data_.data();
  auto kind = [&](std::size_t i) { return kind_[static_cast<unsigned char>(d[i])]; };
  while (pos_ < n && kind(pos_) == kSpace) ++pos_;
  token_line_ = line_;
  if (pos_ >= n || kind(pos_) == kNewline) return false;
  if (kind(pos_) == kComment) {
    while (pos_ < n && d[pos_] != '\n') ++pos_;
    return false;
  }
  const std::size_t start = pos_;
  while (pos_ < n && kind(pos_) == kToken) ++pos_;
  token = std::string_view(d + start, pos_ - start);
  return true;
}

void TextReader::fail(const std::string& message) const {
  throw IoError(path_ + ":" + std::to_string(token_line_) + ": " + message);
}

void TextReader::fail_expected(const char* what, std::string_view found) const {
  std::string f(found.substr(0, 40));
  fail(std::string("expected ") + what + ", found '" + f + "'");
}

ByteReader ByteReader::from_file(const std::string& path) { return ByteReader(read_file_contents(path), path); }

const char* ByteReader::bytes(std::size_t n, const char* what) {
  if (n > data_.size() || pos_ > data_.size() - n)
    fail(std::string("truncated file, expected ") + what + " (" + std::to_string(n) + " bytes) but only " +
         std::to_string(data_.size() - std::min(pos_, data_.size())) + " remain");
  const char* p = data_.data() + pos_;
  pos_ += n;
  return p;
}

void ByteReader::fail(const std::string& message) const {
  throw IoError(path_ + ": byte " + std::to_string(pos_) + ": " + message);
}

}  // namespace anisurf
