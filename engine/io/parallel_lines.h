// Lines of numbers parsed on parallel chunks, for the large sections of the
// text formats that writers put one entity per line (Medit's Vertices and
// Triangles, SolAtVertices).
#pragma once
#include <climits>
#include <cstring>
#include <string_view>
#include <vector>

#include "geometry/parallel_chunks.h"
#include "io/text_reader.h"

namespace anisurf {

inline constexpr int kMaxLineTokens = 16;

// The `n` lines after the rest of the reader's current line (blanks only),
// each of exactly `tokens` whitespace-separated tokens and no comment, given
// to take(i, token) on parallel chunks (i the 0-based line, token an array
// of `tokens` views), which stores them and returns false to refuse one.
// True when every line was taken: the reader is then past them. False, with
// nothing consumed, when a line is otherwise, take refused one, or the
// section is small (under min_lines) or no second thread is available: the
// caller then reads token by token as before (and reports what it finds).
template <class Take>
bool parse_lines_in_parallel(TextReader& in, long long n, int tokens, long long min_lines, Take take) {
  if (n < min_lines || n > INT_MAX || tokens < 1 || tokens > kMaxLineTokens || available_threads() < 2) return false;
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
  const std::string_view text = in.text();
  const char comment = in.comment();
  std::size_t p = in.position();
  while (p < text.size() && blank(text[p])) ++p;
  if (p >= text.size() || text[p] != '\n') return false;
  ++p;
  // Chunks of whole lines, each starting after the newline of the line
  // before: every chunk ends with a newline, which stops each scan below.
  const int chunks = chunk_count(static_cast<int>(n), 32768);
  auto first_line = [&](int c) { return n * c / chunks; };
  std::vector<std::size_t> start(static_cast<std::size_t>(chunks) + 1);
  start[0] = p;
  int next_chunk = 1;
  for (long long line = 0; line < n;) {
    const void* newline = std::memchr(text.data() + p, '\n', text.size() - p);
    if (!newline) return false;
    p = static_cast<std::size_t>(static_cast<const char*>(newline) - text.data()) + 1;
    ++line;
    while (next_chunk < chunks && line == first_line(next_chunk)) start[static_cast<std::size_t>(next_chunk++)] = p;
  }
  start[static_cast<std::size_t>(chunks)] = p;
  std::vector<char> taken(static_cast<std::size_t>(chunks), 1);
  run_chunks(chunks, chunks, [&](int c, int, int) {
    const char* x = text.data() + start[static_cast<std::size_t>(c)];
    const char* const end = text.data() + start[static_cast<std::size_t>(c) + 1];
    std::string_view token[kMaxLineTokens];
    for (long long i = first_line(c); x < end; ++i) {
      int k = 0;
      for (;;) {
        while (blank(*x)) ++x;
        if (*x == '\n') break;
        const char* b = x;
        while (!blank(*x) && *x != '\n' && *x != comment) ++x;
        if (*x == comment || k == tokens) {
          taken[static_cast<std::size_t>(c)] = 0;
          return;
        }
        token[k++] = std::string_view(b, static_cast<std::size_t>(x - b));
      }
      ++x;  // the newline
      if (k != tokens || !take(i, token)) {
        taken[static_cast<std::size_t>(c)] = 0;
        return;
      }
    }
  });
  for (char t : taken)
    if (!t) return false;
  in.skip_parsed(p, static_cast<int>(n) + 1);
  return true;
}

}  // namespace anisurf
