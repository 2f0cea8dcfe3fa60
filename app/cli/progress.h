// Progress of `anisurf adapt` on stderr (issue #6). The remesher calls back
// after every pass (Remesher::run); ProgressDisplay turns the reports into
//  - on a terminal: the per-round lines, and below them one live line
//    rewritten in place ('\r', padded with spaces) after every pass, once the
//    run has lasted live_delay seconds: round, pass, a bar of the vertex count
//    against the count the metric predicts, the operations so far and a rate;
//    finish() erases it, so the output ends with the last round line's '\n';
//  - elsewhere (pipes, CI logs): the per-round lines only, never a '\r';
//  - -v 0: nothing; -v 2: one line per pass (no live line).
// The formatters are free functions of numbers (unit-tested).
#pragma once
#include <functional>
#include <string>
#include <string_view>

#include "remesh/remesher.h"

namespace anisurf::cli {

// "[#####-----]": `width` cells inside the brackets, round(fraction * width)
// of them filled; fraction clamped to [0, 1] (NaN: 0). Width <= 0: "".
std::string format_bar(double fraction, int width);

// Closeness of the vertex count to the predicted one: min(V, P) / max(V, P)
// in [0, 1] (1 when equal; meaningful for refining and coarsening metrics
// alike); 0 when either is not positive.
double vertex_progress(double vertices, double predicted);

// `count` per second with a k / M suffix: "850", "12.3k", "4.56M"; "-" when
// seconds <= 0 or the result is not finite.
std::string format_rate(double count, double seconds);

// A count in at most 6 characters: "8123", "78.1k", "282k", "1.25M".
std::string format_count(long long n);

// What the live line shows.
struct LiveStatus {
  int round = 0;                  // 0: the initial swaps
  std::string_view pass;          // "split", "collapse", ...
  long long splits = 0, collapses = 0, swaps = 0, moves = 0;  // since the run began
  int vertices = 0;
  double predicted_vertices = 0;  // <= 0: unknown (no bar)
  double seconds = 0;             // since the run began
};

// One live line, at most columns - 1 characters (no '\r', no '\n'; columns
// <= 0: no limit):
//   "round 3 smooth   [######################--------]  75%  V 14760/~19680  34.5k op/s  split 8123 collapse 512 swap 20411 move 40000  2.0 s"
// Round, pass, bar, percentage, V and rate always (the bar, 10 to 30 cells,
// takes the room left, none on a very narrow terminal); then the counts in
// full, else rounded ("split 292k ..."), and the time, each if it fits.
std::string format_live_line(const LiveStatus& s, int columns);

// The per-round / per-pass line (no '\n'), as before plus the rate of its operations:
//   "   3 round    split   8123 collapse    512 swap  20411 move   40000 | V   14520 T   29036  in band  97.1%  q 0.412/0.921  1.02 s  71.8k op/s"
std::string format_pass_line(const remesh::PassReport& r, std::string_view what);

struct ProgressOptions {
  int verbose = 1;                // 0 nothing, 1 rounds (+ live line), 2 passes
  bool terminal = false;          // the sink is a terminal: live line
  int columns = 80;               // its width
  double live_delay = 0.5;        // seconds of run before the live line appears
  double predicted_vertices = 0;  // predicted_vertex_count(metric_complexity(...))
};

class ProgressDisplay {
 public:
  using Sink = std::function<void(std::string_view)>;
  ProgressDisplay(const ProgressOptions& options, Sink sink);
  ~ProgressDisplay();  // finish()
  ProgressDisplay(const ProgressDisplay&) = delete;
  ProgressDisplay& operator=(const ProgressDisplay&) = delete;

  // After a pass; `elapsed`: wall seconds since the run began.
  void pass(const remesh::PassReport& r, double elapsed);
  // Erases the live line (if any); idempotent. The round lines were printed by pass().
  void finish();

 private:
  void line(const std::string& text);  // a permanent line, below which the live line is redrawn
  void clear_live();
  void draw_live(double elapsed);

  ProgressOptions options_;
  Sink sink_;
  remesh::PassReport round_;  // sums of the round in progress
  LiveStatus live_;
  std::string pass_name_;     // live_.pass points into it
  std::size_t live_length_ = 0;  // characters of the live line on screen (0: none)
  bool live_started_ = false;
};

}  // namespace anisurf::cli
