#include "editor/script.h"

#include <cstdio>
#include <cstdlib>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace anisurf::editor {

bool is_color_mode(const std::string& mode) {
  for (const char* m : kColorModes)
    if (mode == m) return true;
  return false;
}

std::vector<std::string> split_words(const std::string& text) {
  std::string t = text.substr(0, text.find('#'));
  std::istringstream in(t);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

std::vector<ScriptLine> read_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the script");
  std::vector<ScriptLine> out;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    auto words = split_words(text);
    if (words.empty()) continue;
    out.push_back({path, n, text, std::move(words)});
  }
  return out;
}

namespace {

struct LineError {
  std::string message;
};

double number(const ScriptLine& l, std::size_t i, const char* what) {
  if (i >= l.words.size()) throw LineError{l.words[0] + ": missing " + what};
  const std::string& s = l.words[i];
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size())
    throw LineError{l.words[0] + ": " + what + " expects a number, got '" + s + "'"};
  // Underflow to a subnormal or zero is a number; overflow is not.
  if (!std::isfinite(v)) throw LineError{l.words[0] + ": " + what + " is out of range: '" + s + "'"};
  return v;
}

// A whole number >= lowest.
int whole_number(const ScriptLine& l, std::size_t i, const char* what, int lowest) {
  const double x = number(l, i, what);
  if (x < lowest || x != std::floor(x) || x > 1e9)
    throw LineError{l.words[0] + ": " + what + " must be a whole number >= " + std::to_string(lowest) + ", got '" +
                    l.words[i] + "'"};
  return static_cast<int>(x);
}

void arity(const ScriptLine& l, std::size_t lo, std::size_t hi, const char* usage) {
  const std::size_t n = l.words.size() - 1;
  if (n < lo || n > hi) throw LineError{"usage: " + std::string(usage)};
}

bool on_off(const ScriptLine& l, const char* usage) {
  arity(l, 1, 1, usage);
  if (l.words[1] == "on") return true;
  if (l.words[1] == "off") return false;
  throw LineError{"usage: " + std::string(usage)};
}

// The rest of the line after the first `skip` words (expressions may hold spaces).
std::string rest_of(const ScriptLine& l, std::size_t skip) {
  std::string t = l.text.substr(0, l.text.find('#'));
  std::size_t pos = 0;
  for (std::size_t i = 0; i < skip; ++i) {
    pos = t.find_first_not_of(" \t", pos);
    pos = t.find_first_of(" \t", pos);
  }
  const std::size_t a = t.find_first_not_of(" \t", pos);
  const std::size_t b = t.find_last_not_of(" \t");
  return a == std::string::npos ? "" : t.substr(a, b - a + 1);
}

// `cycles N`: run, then cycle + run until N adaptations or a fixed point.
void run_cycles(EditorSession& s, int n, const ScriptLine& l) {
  int previous = -1;
  for (int k = 1; k <= n; ++k) {
    if (k > 1) s.next_cycle();
    s.run();
    s.wait();
    if (const std::string err = s.adaptation_error(); !err.empty()) throw LineError{"cycles: " + err};
    const auto last = s.timeline().back();
    const int vertices = last->mesh.n_vertices();
    std::fprintf(stderr, "%s: cycle %d: %d vertices, %d triangles, in band %.1f%%\n", l.where().c_str(), s.cycle() + 1,
                 vertices, last->mesh.n_triangles(), last->has_report ? 100 * last->report.in_band_share : 0.0);
    if (previous > 0 && std::abs(vertices - previous) <= 0.02 * previous) break;
    previous = vertices;
  }
}

void run_line(const ScriptLine& l, EditorSession& s, ViewState& v, const ScriptHost& host) {
  const std::string& cmd = l.words[0];
  auto need_mesh = [&] {
    if (!s.has_mesh()) throw LineError{cmd + ": no mesh: start the script with open MESH [SOL]"};
  };
  if (cmd == "open") {
    arity(l, 1, 2, "open MESH [SOL]");
    s.open(l.words[1], l.words.size() > 2 ? l.words[2] : "");
    v.fit_request = true;
  } else if (cmd == "metric") {
    need_mesh();
    if (l.words.size() < 3) throw LineError{"usage: metric iso H | size EXPR | hessian EXPR ERR | curvature HAUSD | sol FILE"};
    MetricSettings m = s.settings();
    const std::string& kind = l.words[1];
    if (kind == "iso") {
      arity(l, 2, 2, "metric iso H");
      m.source = MetricSettings::Source::Iso;
      m.iso = number(l, 2, "H");
      if (!(m.iso > 0)) throw LineError{"metric iso: H must be > 0"};
    } else if (kind == "size") {
      m.source = MetricSettings::Source::Size;
      m.size_expr = rest_of(l, 2);
    } else if (kind == "hessian") {
      if (l.words.size() < 4) throw LineError{"usage: metric hessian EXPR ERR"};
      m.source = MetricSettings::Source::Hessian;
      m.hessian_error = number(l, l.words.size() - 1, "ERR");
      std::string e = rest_of(l, 2);
      m.hessian_expr = e.substr(0, e.find_last_of(" \t"));
      while (!m.hessian_expr.empty() && (m.hessian_expr.back() == ' ' || m.hessian_expr.back() == '\t'))
        m.hessian_expr.pop_back();
    } else if (kind == "curvature") {
      arity(l, 2, 2, "metric curvature HAUSD");
      m.source = MetricSettings::Source::Curvature;
      m.hausd = number(l, 2, "HAUSD");
    } else if (kind == "sol") {
      arity(l, 2, 2, "metric sol FILE");
      m.source = MetricSettings::Source::Sol;
      m.sol_path = l.words[2];
    } else {
      throw LineError{"metric: unknown source '" + kind + "' (iso, size, hessian, curvature, sol)"};
    }
    host.set_settings ? host.set_settings(m) : s.set_settings(m);
  } else if (cmd == "hgrad" || cmd == "hmin" || cmd == "hmax" || cmd == "max-aniso" || cmd == "hausd") {
    need_mesh();
    arity(l, 1, 1, (cmd + " VALUE").c_str());
    MetricSettings m = s.settings();
    const double x = number(l, 1, "VALUE");
    if (cmd == "hgrad") m.hgrad = x;
    if (cmd == "hausd") {
      if (!(x >= 0)) throw LineError{"hausd expects a chordal deviation >= 0 (0: none)"};
      m.hausd_bound = x;
    }
    if (cmd == "hmin") m.hmin = x;
    if (cmd == "hmax") {
      if (x < 0) throw LineError{"hmax expects a size > 0, or 0 for none"};
      m.hmax = x > 0 ? x : INFINITY;
    }
    if (cmd == "max-aniso") {
      if (x != 0 && !(x >= 1)) throw LineError{"max-aniso expects a ratio >= 1, or 0 for none"};
      m.max_aniso = x >= 1 ? x : INFINITY;
    }
    if (cmd == "hmin" && x < 0) throw LineError{"hmin expects a size >= 0"};
    host.set_settings ? host.set_settings(m) : s.set_settings(m);
  } else if (cmd == "lmin" || cmd == "lmax") {
    arity(l, 1, 1, (cmd + " L").c_str());
    const double x = number(l, 1, "L");
    const auto& op = s.adapt_settings().remesh.op;
    s.set_band(cmd == "lmin" ? x : op.lmin, cmd == "lmax" ? x : op.lmax);
  } else if (cmd == "brush") {
    if (l.words.size() >= 2 && l.words[1] == "direction") {
      arity(l, 2, 2, "brush direction stroke|max-curvature|min-curvature");
      const std::string& d = l.words[2];
      if (d == "stroke") s.brush().direction = Brush::Direction::Stroke;
      else if (d == "max-curvature") s.brush().direction = Brush::Direction::MaxCurvature;
      else if (d == "min-curvature") s.brush().direction = Brush::Direction::MinCurvature;
      else throw LineError{"usage: brush direction stroke|max-curvature|min-curvature"};
    } else {
      arity(l, 1, 2, "brush set|smooth|erase [STRENGTH]");
      const std::string& m = l.words[1];
      if (m == "set") s.brush().mode = Brush::Mode::Set;
      else if (m == "smooth") s.brush().mode = Brush::Mode::Smooth;
      else if (m == "erase") s.brush().mode = Brush::Mode::Erase;
      else throw LineError{"usage: brush set|smooth|erase [STRENGTH]"};
      if (l.words.size() > 2) {
        const double st = number(l, 2, "STRENGTH");
        if (!(st > 0 && st <= 1)) throw LineError{"brush: STRENGTH must be in (0, 1]"};
        s.brush().strength = st;
      }
    }
  } else if (cmd == "paint") {
    need_mesh();
    if (l.words.size() != 6 && l.words.size() != 10) throw LineError{"usage: paint X Y Z RADIUS SIZE [STRETCH DIRX DIRY DIRZ]"};
    const Vec3 c(number(l, 1, "X"), number(l, 2, "Y"), number(l, 3, "Z"));
    Brush& b = s.brush();
    b.radius = number(l, 4, "RADIUS");
    b.size = number(l, 5, "SIZE");
    if (!(b.radius > 0) || !(b.size > 0)) throw LineError{"paint: RADIUS and SIZE must be > 0"};
    // The sizes must give a metric: 1 / h^2 finite and > 0.
    Vec3 dir;
    b.stretch = 1;
    if (l.words.size() == 10) {
      b.stretch = number(l, 6, "STRETCH");
      if (!(b.stretch >= 1)) throw LineError{"paint: STRETCH must be >= 1"};
      dir = Vec3(number(l, 7, "DIRX"), number(l, 8, "DIRY"), number(l, 9, "DIRZ"));
      if (b.direction == Brush::Direction::Stroke && !(norm2(dir) > 0)) throw LineError{"paint: the direction is zero"};
    }
    for (const double h : {b.size, b.size * b.stretch})
      if (!std::isnormal(1.0 / (h * h)))
        throw LineError{"paint: a size of " + l.words[5] + (b.stretch > 1 ? " x " + l.words[6] : std::string()) +
                        " gives no metric (1/h^2 must be a finite number > 0)"};
    s.dab(c, dir);
  } else if (cmd == "stroke") {
    need_mesh();
    arity(l, 1, 1, "stroke begin|end");
    if (l.words[1] == "begin") s.begin_stroke();
    else if (l.words[1] == "end") s.end_stroke();
    else throw LineError{"usage: stroke begin|end"};
  } else if (cmd == "undo" || cmd == "redo") {
    arity(l, 0, 0, cmd.c_str());
    if (!(cmd == "undo" ? s.undo() : s.redo())) throw LineError{cmd + ": nothing to " + cmd};
  } else if (cmd == "step") {
    need_mesh();
    arity(l, 0, 0, "step");
    s.step();
  } else if (cmd == "run") {
    need_mesh();
    arity(l, 0, 1, "run [MAXPASSES]");
    int n = 0;
    if (l.words.size() > 1) {
      const double x = number(l, 1, "MAXPASSES");
      if (x < 1 || x != std::floor(x)) throw LineError{"run: MAXPASSES must be a whole number >= 1"};
      n = static_cast<int>(x);
    }
    s.run(n);
  } else if (cmd == "cycle" || cmd == "cycles") {
    // cycle: the displayed mesh becomes T_0, its metric derived again;
    // cycles N: run, then N - 1 times cycle + run, stopping at a fixed point
    // (the vertex count within 2% of the previous cycle's), as `anisurf adapt
    // --cycles N`; one line per cycle on stderr.
    need_mesh();
    if (cmd == "cycle") {
      arity(l, 0, 0, "cycle");
      s.next_cycle();
    } else {
      arity(l, 1, 1, "cycles N");
      const double x = number(l, 1, "N");
      if (x < 1 || x != std::floor(x) || x > 1000) throw LineError{"cycles: N must be a whole number in [1, 1000]"};
      run_cycles(s, static_cast<int>(x), l);
    }
  } else if (cmd == "reset") {
    arity(l, 0, 0, "reset");
    s.reset();
  } else if (cmd == "timeline") {
    arity(l, 1, 1, "timeline I");
    s.scrub(whole_number(l, 1, "I", 0));
  } else if (cmd == "select-bin") {
    need_mesh();
    arity(l, 2, 2, "select-bin length|quality I|worst");
    BinKind k;
    if (!parse_bin_kind(l.words[1], &k)) throw LineError{"usage: select-bin length|quality I|worst"};
    if (l.words[2] == "worst") {
      // The lowest non-empty quality bin; for lengths the outermost non-empty
      // bin on the side farther from the band (longest first).
      const int n = bin_count(k);
      const bool quality = k == BinKind::Quality;
      for (int j = 0; j < n; ++j) {
        s.select_bin(k, quality ? j : n - 1 - j);
        if (!s.selection().triangles.empty()) break;
      }
    } else {
      const double i = number(l, 2, "I");
      if (i != std::floor(i)) throw LineError{"select-bin: I must be a bin number or 'worst'"};
      s.select_bin(k, static_cast<int>(i));
    }
    if (s.selection().triangles.empty()) throw LineError{"select-bin: bin " + l.words[2] + " is empty"};
    v.frame_selection = true;
  } else if (cmd == "clear-selection") {
    s.clear_selection();
  } else if (cmd == "view") {
    arity(l, 1, 1, "view NAME");
    auto nv = render::parse_view(l.words[1]);
    if (!nv) throw LineError{"view: expects " + render::view_names() + ", got '" + l.words[1] + "'"};
    v.view_request = *nv;
  } else if (cmd == "color") {
    arity(l, 1, 1, "color MODE");
    if (!is_color_mode(l.words[1]))
      throw LineError{"color: expects size|aniso|length|quality|ref|deviation|distance|fallback|none, got '" + l.words[1] +
                      "'"};
    if (l.words[1] == "deviation" && v.bezier == 0) throw LineError{"color deviation: show the G1 surface first (bezier K)"};
    if (colors_mesh_only(l.words[1]) && v.bezier > 0)
      throw LineError{"color " + l.words[1] + ": the " + (l.words[1] == "distance" ? "distance colours" : "placements colour") +
                      " the mesh; hide the G1 surface first (bezier off)"};
    v.color = l.words[1];
  } else if (cmd == "glyphs") {
    v.glyphs = on_off(l, "glyphs on|off");
  } else if (cmd == "touched") {
    v.show_touched = on_off(l, "touched on|off");
  } else if (cmd == "wire") {
    v.wireframe = on_off(l, "wire on|off");
  } else if (cmd == "control-net") {
    v.control_net = on_off(l, "control-net on|off");
  } else if (cmd == "bezier") {
    arity(l, 1, 1, "bezier K|off");
    if (l.words[1] == "off") {
      v.bezier = 0;
      if (v.color == "deviation") v.color = "size";
    } else {
      const double k = number(l, 1, "K");
      if (k < 1 || k > 16 || k != std::floor(k)) throw LineError{"bezier: K must be a whole number in [1, 16]"};
      v.bezier = static_cast<int>(k);
      if (colors_mesh_only(v.color)) v.color = "size";  // the G1 surface hides the mesh they colour
    }
  } else if (cmd == "screenshot") {
    arity(l, 1, 1, "screenshot PNG");
    if (!host.screenshot) throw LineError{"screenshot: no renderer"};
    // Checked here, at the line (a mistyped directory is refused, never made).
    check_writable(l.words[1]);
    host.screenshot(l.words[1]);
  } else if (cmd == "click") {
    need_mesh();
    arity(l, 2, 2, "click X Y");
    const double x = number(l, 1, "X"), y = number(l, 2, "Y");
    if (x < 0 || y < 0) throw LineError{"click: X and Y are pixels from the window's top-left corner (>= 0)"};
    if (!host.click) throw LineError{"click: no window"};
    host.click(static_cast<float>(x), static_cast<float>(y));
  } else if (cmd == "keys") {
    const bool on = on_off(l, "keys on|off");
    if (!host.show_keys) throw LineError{"keys: no window"};
    host.show_keys(on);
  } else if (cmd == "save") {
    need_mesh();
    arity(l, 1, 2, "save MESH [SOL]");
    s.wait();
    s.save(l.words[1], l.words.size() > 2 ? l.words[2] : "");
  } else if (cmd == "frame-stats") {
    arity(l, 0, 1, "frame-stats [reset]");
    if (l.words.size() > 1 && l.words[1] != "reset") throw LineError{"usage: frame-stats [reset]"};
    if (!host.frame_stats) throw LineError{"frame-stats: the window's frame times (run the script without --headless)"};
    host.frame_stats(l.words.size() > 1);
  } else if (cmd == "quit") {
    arity(l, 0, 0, "quit");
    if (host.quit) host.quit();
  } else {
    throw LineError{"unknown command '" + cmd + "' (see anisurf --help-script)"};
  }
}

}  // namespace

void execute(const ScriptLine& line, EditorSession& session, ViewState& view, const ScriptHost& host) {
  try {
    run_line(line, session, view, host);
  } catch (const LineError& e) {
    throw Error(line.where() + ": " + e.message);
  } catch (const std::exception& e) {
    throw Error(line.where() + ": " + line.words[0] + ": " + e.what());
  }
}

const char* script_help() {
  return "Script commands (one per line, '#' comments):\n"
         "  open MESH [SOL]                        load a mesh (and its metric)\n"
         "  metric iso H                           isotropic size H\n"
         "  metric size EXPR                       size h(x,y,z) (muParser)\n"
         "  metric hessian EXPR ERR                Hessian metric of f(x,y,z), error ERR\n"
         "  metric curvature HAUSD                 geometric metric, chordal deviation HAUSD\n"
         "  metric sol FILE                        metric read from a .sol\n"
         "  hgrad R | hmin A | hmax B | max-aniso K  gradation and bounds (hgrad <= 1: off;\n"
         "                                         hmax 0, max-aniso 0: none)\n"
         "  hausd D                                bound the chordal deviation: the metric is\n"
         "                                         intersected with the curvature metric of D\n"
         "                                         (Mmg's -hausd; 0: a Hessian metric gets\n"
         "                                         diagonal/1000 as in `anisurf adapt`, a\n"
         "                                         loaded one none)\n"
         "  brush set|smooth|erase [STRENGTH]      brush mode and strength (0, 1]\n"
         "  brush direction stroke|max-curvature|min-curvature\n"
         "  paint X Y Z RADIUS SIZE [STRETCH DIRX DIRY DIRZ]\n"
         "                                         one dab: blend the metric towards SIZE\n"
         "                                         (SIZE x STRETCH along DIR) within RADIUS\n"
         "  stroke begin | stroke end              dabs in between are one edit (one undo)\n"
         "  undo | redo                            metric edits\n"
         "  step | run [MAXPASSES] | reset         adaptation (one pass / until converged)\n"
         "  cycle | cycles N                       section 7.1's loop: the adapted mesh becomes\n"
         "                                         T_0 and its metric is derived again (cycles N:\n"
         "                                         N adaptations, stopping at a fixed point)\n"
         "  lmin L | lmax L                        edge length band (default 0.72, 1.4)\n"
         "  timeline I                             show pass I of the timeline (0: initial)\n"
         "  select-bin length|quality I|worst      highlight a histogram bin (worst: the lowest\n"
         "                                         quality / longest length bin), frame its worst\n"
         "  clear-selection\n"
         "  view iso|front|back|top|bottom|left|right\n"
         "  color size|aniso|length|quality|ref|deviation|distance|fallback|none\n"
         "                                         (deviation: the mesh to its G1 surface, with\n"
         "                                         bezier K; distance: the mesh to the input\n"
         "                                         surface T_G, measured after each pass shown;\n"
         "                                         fallback: each vertex on the G1 surface, pulled\n"
         "                                         back to the input where the G1 surface strayed\n"
         "                                         beyond the input bound, or off the surface)\n"
         "  glyphs on|off | wire on|off | touched on|off (vertices the shown pass touched)\n"
         "  bezier K|off | control-net on|off\n"
         "  click X Y                              a click (no drag) at pixel X, Y from the top-left:\n"
         "                                         pins the element under it (elsewhere: unpins)\n"
         "  keys on|off                            the window listing the keys (F1)\n"
         "  screenshot PNG | save MESH [SOL] | quit\n"
         "  frame-stats [reset]                    the window's frame times since the start or\n"
         "                                         the last reset: frames, mean, slowest (and\n"
         "                                         what ran then); reset clears them\n";
}

}  // namespace anisurf::editor
