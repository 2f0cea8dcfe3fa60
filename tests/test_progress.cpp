// The progress display of `anisurf adapt` (app/cli/progress.h): the
// formatters from numbers, and the display fed with pass reports.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cli/progress.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::cli;

namespace {

int count(const std::string& s, char c) {
  int n = 0;
  for (char x : s) n += x == c;
  return n;
}

using test::render_terminal;

// A run of `rounds` rounds (split, collapse, swap, smooth) after the initial
// swaps, then the final pass; vertices grow by 1000 per round.
std::vector<remesh::PassReport> fake_run(int rounds) {
  std::vector<remesh::PassReport> out;
  auto add = [&](remesh::PassKind k, int it, int v) {
    remesh::PassReport r;
    r.kind = k;
    r.round = it;
    r.vertices = v;
    r.triangles = 2 * v;
    r.seconds = 0.25;
    switch (k) {
      case remesh::PassKind::Split: r.splits = 1000; break;
      case remesh::PassKind::Collapse: r.collapses = 100; break;
      case remesh::PassKind::Swap: r.swaps = 500; break;
      default: r.moves = 2000;
    }
    out.push_back(r);
  };
  add(remesh::PassKind::Swap, 0, 1000);
  for (int i = 1; i <= rounds; ++i) {
    add(remesh::PassKind::Split, i, 1000 + 1000 * i);
    add(remesh::PassKind::Collapse, i, 1000 + 1000 * i);
    add(remesh::PassKind::Swap, i, 1000 + 1000 * i);
    add(remesh::PassKind::Smooth, i, 1000 + 1000 * i);
  }
  add(remesh::PassKind::Final, rounds + 1, 1000 + 1000 * rounds);
  return out;
}

// The display's output for fake_run(rounds), pass k at elapsed k * step seconds.
std::string play(const ProgressOptions& o, int rounds, double step = 0.25) {
  std::string out;
  {
    ProgressDisplay d(o, [&](std::string_view s) { out += s; });
    const auto passes = fake_run(rounds);
    for (std::size_t k = 0; k < passes.size(); ++k) d.pass(passes[k], step * (k + 1));
    d.finish();
  }
  return out;
}

}  // namespace

TEST_CASE("progress: format_bar fills round(fraction * width) cells, fraction clamped to [0, 1]") {
  CHECK(format_bar(0.5, 10) == "[#####-----]");
  CHECK(format_bar(0.0, 4) == "[----]");
  CHECK(format_bar(1.0, 4) == "[####]");
  CHECK(format_bar(0.26, 20) == "[#####---------------]");
  CHECK(format_bar(-3.0, 5) == "[-----]");
  CHECK(format_bar(7.0, 5) == "[#####]");
  CHECK(format_bar(std::numeric_limits<double>::quiet_NaN(), 5) == "[-----]");
  CHECK(format_bar(0.5, 0).empty());
  for (int w : {1, 7, 30}) CHECK(format_bar(0.33, w).size() == static_cast<std::size_t>(w) + 2);
}

TEST_CASE("progress: vertex_progress is the closeness of V to the prediction, in [0, 1]") {
  CHECK(vertex_progress(50, 100) == doctest::Approx(0.5));
  CHECK(vertex_progress(200, 100) == doctest::Approx(0.5));  // coarsening metrics too
  CHECK(vertex_progress(100, 100) == doctest::Approx(1.0));
  CHECK(vertex_progress(0, 100) == 0);
  CHECK(vertex_progress(10, 0) == 0);
  CHECK(vertex_progress(10, -5) == 0);
}

TEST_CASE("progress: format_rate with k / M suffixes, '-' without time") {
  CHECK(format_rate(0, 1) == "0");
  CHECK(format_rate(850, 1) == "850");
  CHECK(format_rate(425, 0.5) == "850");
  CHECK(format_rate(12345, 1) == "12.3k");
  CHECK(format_rate(999.6, 1) == "1.0k");
  CHECK(format_rate(4.56e6, 1) == "4.56M");
  CHECK(format_rate(5, 0) == "-");
  CHECK(format_rate(5, -1) == "-");
  CHECK(format_rate(std::numeric_limits<double>::infinity(), 1) == "-");
}

TEST_CASE("progress: format_count in at most 6 characters") {
  CHECK(format_count(0) == "0");
  CHECK(format_count(8123) == "8123");
  CHECK(format_count(78090) == "78.1k");
  CHECK(format_count(99960) == "100k");
  CHECK(format_count(282447) == "282k");
  CHECK(format_count(999600) == "1.00M");
  CHECK(format_count(1250000) == "1.25M");
}

TEST_CASE("progress: the live line (round, pass, bar, clamped percentage, V / prediction, rate, counts)") {
  LiveStatus s;
  s.round = 3;
  s.pass = "smooth";
  s.splits = 8123;
  s.collapses = 512;
  s.swaps = 20411;
  s.moves = 40000;
  s.vertices = 14760;
  s.predicted_vertices = 19680;
  s.seconds = 2.0;
  const std::string wide = format_live_line(s, 0);  // no width limit: the widest bar
  CHECK(wide.rfind("round 3 smooth ", 0) == 0);
  CHECK(wide.find("[" + std::string(23, '#') + std::string(7, '-') + "]  75%") != std::string::npos);
  CHECK(wide.find("V 14760/~19680") != std::string::npos);
  CHECK(wide.find("34.5k op/s") != std::string::npos);  // 69046 operations in 2 s
  CHECK(wide.find("op/s  split 8123 collapse 512 swap 20411 move 40000  2.0 s") != std::string::npos);
  CHECK(wide.find('\r') == std::string::npos);
  CHECK(wide.find('\n') == std::string::npos);

  // More vertices than predicted: the percentage stays <= 100 (here 50%).
  s.vertices = 2 * 19680;
  const std::string over = format_live_line(s, 0);
  CHECK(over.find(" 50%") != std::string::npos);
  s.vertices = 19680;
  CHECK(format_live_line(s, 0).find("[" + std::string(30, '#') + "] 100%") != std::string::npos);

  // A terminal's width: at most columns - 1 characters; the bar shrinks first,
  // then the counts at the end are cut; a narrow terminal has no bar.
  for (int columns : {200, 132, 100, 80, 60, 40, 20}) {
    CAPTURE(columns);
    const std::string l = format_live_line(s, columns);
    CHECK(static_cast<int>(l.size()) <= columns - 1);
    CHECK(l.rfind("round 3", 0) == 0);
  }
  const std::string l132 = format_live_line(s, 132);
  CHECK(l132.size() == 131);  // the bar takes the room left
  CHECK(l132.find("move 40000") != std::string::npos);
  // 80 columns: no room for the counts (the per-round lines have them); the time fits.
  const std::string l80 = format_live_line(s, 80);
  CHECK(l80.find("[" + std::string(20, '#') + "] 100%") != std::string::npos);
  CHECK(l80.find("op/s  2.0 s") != std::string::npos);
  CHECK(l80.find("split") == std::string::npos);
  // 109 columns, larger counts: the counts rounded, the smallest bar, no time.
  LiveStatus big = s;
  big.swaps = 282447;
  big.moves = 625646;
  const std::string l109 = format_live_line(big, 109);
  CHECK(l109.size() == 108);
  CHECK(l109.find("[##########]") != std::string::npos);
  CHECK(l109.find("458.4k op/s  split 8123 collapse 512 swap 282k move 626k") != std::string::npos);
  CHECK(l109.find("2.0 s") == std::string::npos);
  CHECK(format_live_line(big, 113).find("swap 282447 move 625646") != std::string::npos);
  CHECK(format_live_line(s, 40).find('[') == std::string::npos);

  // Unknown prediction: no bar, no percentage. Round 0: the initial swaps.
  s.predicted_vertices = 0;
  s.round = 0;
  s.pass = "swap";
  const std::string unknown = format_live_line(s, 0);
  CHECK(unknown.rfind("initial swap", 0) == 0);
  CHECK(unknown.find('[') == std::string::npos);
  CHECK(unknown.find('%') == std::string::npos);
  CHECK(unknown.find("V 19680  ") != std::string::npos);
}

TEST_CASE("progress: the per-round / per-pass line has the counts, the state and the rate") {
  remesh::PassReport r;
  r.round = 4;
  r.splits = 600;
  r.collapses = 200;
  r.swaps = 150;
  r.moves = 50;
  r.vertices = 14520;
  r.triangles = 29036;
  r.in_band_share = 0.971;
  r.q_min = 0.412;
  r.q_mean = 0.921;
  r.seconds = 0.5;
  const std::string l = format_pass_line(r, "round");
  CHECK(l == "   4 round    split    600 collapse    200 swap    150 move      50 | V   14520 T   29036  in band  97.1%  "
             "q 0.412/0.921  0.50 s  2.0k op/s");
  r.seconds = 0;
  CHECK(format_pass_line(r, "round").find("0.00 s  - op/s") != std::string::npos);
}

TEST_CASE("progress display, not a terminal: one line per round and the final one, never a '\\r'") {
  ProgressOptions o;
  o.terminal = false;
  o.predicted_vertices = 5000;
  o.live_delay = 0;
  const std::string out = play(o, 3);
  CHECK(count(out, '\r') == 0);
  CHECK(count(out, '\n') == 4);
  REQUIRE(!out.empty());
  CHECK(out.back() == '\n');
  const auto lines = render_terminal(out);
  REQUIRE(lines.size() == 5);
  CHECK(lines[0].rfind("   1 round    split   1000 collapse    100 swap    500 move    2000 | V    2000", 0) == 0);
  CHECK(lines[0].find("1.00 s  3.6k op/s") != std::string::npos);  // 3600 operations in 4 passes of 0.25 s
  CHECK(lines[2].rfind("   3 round", 0) == 0);
  CHECK(lines[3].rfind("   4 final", 0) == 0);
  CHECK(lines[4].empty());
}

TEST_CASE("progress display, terminal: a live line rewritten after every pass, erased at the end") {
  ProgressOptions o;
  o.terminal = true;
  o.columns = 0;  // no width limit: a bar of 30
  o.predicted_vertices = 5000;
  o.live_delay = 0;
  const std::string out = play(o, 3);
  // A live line after each of the 13 passes before the final one.
  CHECK(count(out, '\r') >= 13);
  CHECK(out.find("\rinitial swap ") != std::string::npos);
  CHECK(out.find("\rround 2 collapse ") != std::string::npos);
  CHECK(out.find("\rround 3 smooth   [" + std::string(24, '#') + std::string(6, '-') + "]") != std::string::npos);
  CHECK(out.find(" 80%  V 4000/~5000") != std::string::npos);
  REQUIRE(!out.empty());
  CHECK(out.back() == '\n');
  // On screen: the same lines as without a terminal, the live line gone.
  ProgressOptions pipe = o;
  pipe.terminal = false;
  CHECK(render_terminal(out) == render_terminal(play(pipe, 3)));
  for (const auto& l : render_terminal(out)) CHECK(l.find("op/s  ") == std::string::npos);  // (only the live line has "op/s  ")
}

TEST_CASE("progress display: the live line waits for live_delay, -v 0 prints nothing, -v 2 one line per pass") {
  ProgressOptions o;
  o.terminal = true;
  o.predicted_vertices = 5000;
  o.live_delay = 2.6;  // passes every 0.25 s: the live line from the 11th pass on (round 3's collapse)
  const std::string late = play(o, 3);
  CHECK(late.find("\rround 1 ") == std::string::npos);
  CHECK(late.find("\rround 3 split") == std::string::npos);
  CHECK(late.find("\rround 3 collapse") != std::string::npos);
  CHECK(late.find("\rround 3 swap") != std::string::npos);
  o.live_delay = 100;
  CHECK(count(play(o, 3), '\r') == 0);

  o.verbose = 0;
  o.live_delay = 0;
  CHECK(play(o, 3).empty());

  o.verbose = 2;
  const std::string passes = play(o, 3);
  CHECK(count(passes, '\r') == 0);
  CHECK(count(passes, '\n') == 14);  // initial swap, 3 x 4 passes, final
  const auto lines = render_terminal(passes);
  CHECK(lines[0].rfind("   0 swap ", 0) == 0);
  CHECK(lines[2].rfind("   1 collapse ", 0) == 0);
  CHECK(lines[13].rfind("   4 final ", 0) == 0);
}
