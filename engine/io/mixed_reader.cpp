#include "io/mixed_reader.h"

#include <algorithm>

#include "core/error.h"
#include "io/text_reader.h"

namespace anisurf {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

}  // namespace

void MixedReader::skip_space() {
  while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
}

bool MixedReader::skip_past(std::string_view marker) {
  const std::size_t at = data_.find(marker, pos_);
  if (at == std::string::npos) return false;
  pos_ = at + marker.size();
  return true;
}

bool MixedReader::at_end() {
  skip_space();
  return pos_ >= data_.size();
}

std::string_view MixedReader::token(const char* what) {
  skip_space();
  token_start_ = pos_;
  if (pos_ >= data_.size()) fail(std::string("unexpected end of file, expected ") + what);
  const std::size_t start = pos_;
  while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
  return std::string_view(data_).substr(start, pos_ - start);
}

std::string_view MixedReader::peek() {
  const std::size_t p = pos_, t = token_start_;
  skip_space();
  std::string_view out;
  if (pos_ < data_.size()) out = token("token");
  pos_ = p;
  token_start_ = t;
  return out;
}

long long MixedReader::read_int(const char* what, long long lo, long long hi) {
  const std::string_view t = token(what);
  long long v = 0;
  if (!parse_integer(t, v)) fail_expected(what, t);
  if (v < lo || v > hi)
    fail(std::string(what) + " " + std::to_string(v) + " out of range, expected " + std::to_string(lo) + ".." +
         std::to_string(hi));
  return v;
}

double MixedReader::read_double(const char* what) {
  const std::string_view t = token(what);
  double v = 0;
  if (!parse_real(t, v)) fail_expected(what, t);
  return v;
}

void MixedReader::expect(std::string_view expected) {
  const std::string e(expected);
  const std::string_view t = token(("'" + e + "'").c_str());
  if (t != expected) fail_expected(("'" + e + "'").c_str(), t);
}

std::string_view MixedReader::rest_of_line() {
  while (pos_ < data_.size() && (data_[pos_] == ' ' || data_[pos_] == '\t')) ++pos_;
  token_start_ = pos_;
  const std::size_t start = pos_;
  while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  std::size_t end = pos_;
  if (end > start && data_[end - 1] == '\r') --end;
  if (pos_ < data_.size()) ++pos_;
  return std::string_view(data_).substr(start, end - start);
}

void MixedReader::skip_line_end() {
  while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
  if (pos_ < data_.size()) ++pos_;
}

const char* MixedReader::bytes(std::size_t n, const char* what) {
  token_start_ = pos_;
  if (n > remaining())
    fail(std::string("truncated file, expected ") + what + " (" + std::to_string(n) + " bytes) but only " +
         std::to_string(remaining()) + " remain");
  const char* p = data_.data() + pos_;
  pos_ += n;
  return p;
}

void MixedReader::check_fits(long long count, std::size_t min_bytes, const char* what) {
  const auto room = static_cast<unsigned long long>(remaining());
  if (count < 0 || (min_bytes > 0 && static_cast<unsigned long long>(count) > room / min_bytes))
    fail(std::string(what) + " count " + std::to_string(count) + " impossible: the " + std::to_string(room) +
         " bytes left in the file hold at most " + std::to_string(min_bytes ? room / min_bytes : room) +
         ", expected a count that fits the file");
}

int MixedReader::line_at(std::size_t offset) const {
  offset = std::min(offset, data_.size());
  return 1 + static_cast<int>(std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

void MixedReader::fail(const std::string& message) const {
  if (binary_) throw IoError(path_ + ": byte " + std::to_string(token_start_) + ": " + message);
  throw IoError(path_ + ":" + std::to_string(line_at(token_start_)) + ": " + message);
}

void MixedReader::fail_expected(const char* what, std::string_view found) const {
  fail(std::string("expected ") + what + ", found " + quoted(found));
}

}  // namespace anisurf
