#include "cli/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace anisurf::cli {

namespace {

template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof buf, fmt, args...);
  return std::string(buf, static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(sizeof buf) - 1)));
}

constexpr int kMaxBar = 30, kMinBar = 10;

}  // namespace

std::string format_bar(double fraction, int width) {
  if (width <= 0) return {};
  if (!(fraction > 0)) fraction = 0;  // NaN too
  fraction = std::min(fraction, 1.0);
  const int filled = std::clamp(static_cast<int>(std::lround(fraction * width)), 0, width);
  std::string bar(static_cast<std::size_t>(width) + 2, '-');
  bar.front() = '[';
  bar.back() = ']';
  std::fill_n(bar.begin() + 1, filled, '#');
  return bar;
}

double vertex_progress(double vertices, double predicted) {
  if (!(vertices > 0) || !(predicted > 0)) return 0;
  return std::min(vertices, predicted) / std::max(vertices, predicted);
}

std::string format_rate(double count, double seconds) {
  if (!(seconds > 0)) return "-";
  const double r = count / seconds;
  if (!std::isfinite(r) || r < 0) return "-";
  if (r < 999.5) return format("%.0f", r);
  if (r < 999.5e3) return format("%.1fk", r / 1e3);
  return format("%.2fM", r / 1e6);
}

std::string format_count(long long n) {
  const double x = static_cast<double>(n);
  if (n < 10000 && n > -10000) return format("%lld", n);
  if (x < 99.95e3 && x > -99.95e3) return format("%.1fk", x / 1e3);
  if (x < 999.5e3 && x > -999.5e3) return format("%.0fk", x / 1e3);
  return format("%.2fM", x / 1e6);
}

std::string format_live_line(const LiveStatus& s, int columns) {
  const std::string label = s.round > 0 ? format("round %d", s.round) : std::string("initial");
  const std::string pass(s.pass);
  const std::string head = format("%s %-8s ", label.c_str(), pass.c_str());
  const bool known = s.predicted_vertices > 0;
  const double fraction = vertex_progress(s.vertices, s.predicted_vertices);
  const std::string percent = known ? format(" %3d%%", static_cast<int>(std::floor(100 * fraction))) : std::string();
  std::string tail = format("  V %d", s.vertices);
  if (known) tail += format("/~%.0f", s.predicted_vertices);
  const long long ops = s.splits + s.collapses + s.swaps + s.moves;
  tail += "  " + format_rate(static_cast<double>(ops), s.seconds) + " op/s";
  // Optional fields, each kept if it fits next to the smallest bar: the counts
  // (in full, else rounded), then the time.
  const std::string counts[] = {
      format("  split %lld collapse %lld swap %lld move %lld", s.splits, s.collapses, s.swaps, s.moves),
      "  split " + format_count(s.splits) + " collapse " + format_count(s.collapses) + " swap " +
          format_count(s.swaps) + " move " + format_count(s.moves)};
  const std::string elapsed = format("  %.1f s", s.seconds);

  const int limit = columns > 0 ? columns - 1 : 1 << 20;
  const auto size = [](const std::string& t) { return static_cast<int>(t.size()); };
  int used = size(head) + size(percent) + size(tail);
  // No bar on a terminal too narrow for the essential fields and the smallest bar.
  const int min_bar = known && used + kMinBar + 2 <= limit ? kMinBar + 2 : 0;
  for (const std::string& c : counts)
    if (used + min_bar + size(c) <= limit) {
      tail += c;
      used += size(c);
      break;
    }
  if (used + min_bar + size(elapsed) <= limit) {
    tail += elapsed;
    used += size(elapsed);
  }
  const int bar = min_bar > 0 ? std::clamp(limit - used - 2, kMinBar, kMaxBar) : 0;
  std::string line = head + format_bar(fraction, bar) + percent + tail;
  if (size(line) > limit) line.resize(static_cast<std::size_t>(std::max(limit, 0)));
  return line;
}

std::string format_pass_line(const remesh::PassReport& r, std::string_view what) {
  const std::string w(what);
  return format("  %2d %-8s split %6d collapse %6d swap %6d move %7d | V %7d T %7d  in band %5.1f%%  q %.3f/%.3f  "
                "%.2f s  %s op/s",
                r.round, w.c_str(), r.splits, r.collapses, r.swaps, r.moves, r.vertices,
                r.triangles, 100 * r.in_band_share, r.q_min, r.q_mean, r.seconds,
                format_rate(r.changes(), r.seconds).c_str());
}

ProgressDisplay::ProgressDisplay(const ProgressOptions& options, Sink sink)
    : options_(options), sink_(std::move(sink)) {
  live_.predicted_vertices = options_.predicted_vertices;
}

ProgressDisplay::~ProgressDisplay() { finish(); }

void ProgressDisplay::clear_live() {
  if (live_length_ == 0) return;
  std::string erase(live_length_ + 2, ' ');
  erase.front() = erase.back() = '\r';
  sink_(erase);
  live_length_ = 0;
}

void ProgressDisplay::line(const std::string& text) {
  clear_live();
  sink_(text + "\n");
}

void ProgressDisplay::draw_live(double elapsed) {
  if (!options_.terminal || options_.verbose != 1) return;
  if (!live_started_ && !(elapsed >= options_.live_delay)) return;
  live_started_ = true;
  live_.seconds = elapsed;
  const std::string text = format_live_line(live_, options_.columns);
  // Spaces over what is left of a longer line before (no escape sequence:
  // works on a dumb terminal too).
  const std::size_t pad = live_length_ > text.size() ? live_length_ - text.size() : 0;
  std::string out(1, '\r');
  out.append(text).append(pad, ' ');
  sink_(out);
  live_length_ = text.size() + pad;
}

void ProgressDisplay::pass(const remesh::PassReport& r, double elapsed) {
  if (options_.verbose <= 0) return;
  // Regions remeshed at once (--threads) report their passes interleaved:
  // each pass line (-v 2) or each region's final line (-v 1) names its region.
  const std::string name = r.region >= 0 ? "region " + std::to_string(r.region) + " " + std::string(remesh::pass_name(r.kind))
                                         : std::string(remesh::pass_name(r.kind));
  live_.round = r.round;
  pass_name_ = name;
  live_.pass = pass_name_;
  live_.splits += r.splits;
  live_.collapses += r.collapses;
  live_.swaps += r.swaps;
  live_.moves += r.moves + r.removed_vertices;
  live_.vertices = r.vertices;
  if (options_.verbose >= 2) {
    line(format_pass_line(r, name));
    return;
  }
  if (r.region >= 0) {
    if (r.kind == remesh::PassKind::Final) line(format_pass_line(r, name));
    else draw_live(elapsed);
    return;
  }
  // -v 1: the sums of a round, printed when the next round (or the final pass)
  // begins; the initial swaps (round 0) are only counted on the live line.
  if (r.kind == remesh::PassKind::Final || r.round != round_.round) {
    if (round_.round > 0) line(format_pass_line(round_, "round"));
    round_ = remesh::PassReport{};
    round_.round = r.round;
  }
  if (r.kind == remesh::PassKind::Final) {
    line(format_pass_line(r, "final"));
    return;  // the run is over: no live line after the final one
  }
  round_.splits += r.splits;
  round_.collapses += r.collapses;
  round_.swaps += r.swaps;
  round_.moves += r.moves + r.removed_vertices;
  round_.seconds += r.seconds;
  round_.vertices = r.vertices;
  round_.triangles = r.triangles;
  round_.in_band_share = r.in_band_share;
  round_.q_min = r.q_min;
  round_.q_mean = r.q_mean;
  draw_live(elapsed);
}

void ProgressDisplay::finish() { clear_live(); }

}  // namespace anisurf::cli
