// The editor: the session in process (undo / redo restore the metric
// exactly, the brush changes the metric only within its radius, the
// adaptation's timeline, bin selections, script errors naming the line), and
// tests/data/scripts/panels.anisurf, which drives every panel's action, run
// headless (OSMesa) and in the window under xvfb-run when available, with
// checks on its screenshots.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "editor/analysis.h"
#include "editor/editor_view.h"
#include "editor/script.h"
#include "editor/session.h"
#include "io/mesh_io.h"
#include "locate/surface_distance.h"
#include "remesh/adapt.h"
#include "remesh/adapted_mesh.h"
#include "render/bezier_structure.h"
#include "render/image.h"
#include "render/mesh_structure.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;

namespace {

std::filesystem::path assets_dir() { return std::filesystem::path(ANISURF_TEST_DATA_DIR) / ".." / ".." / "assets"; }
std::string demo_mesh() { return (assets_dir() / "demo.mesh").string(); }
std::string demo_sol() { return (assets_dir() / "demo.sol").string(); }

bool same(const MetricField& a, const MetricField& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].m != b[i].m) return false;
  return true;
}

double tangent_size(const SymTensor3& M) {
  const auto sd = sizes_and_directions(M);
  auto s = sd.sizes;
  std::sort(s.begin(), s.end());
  return std::sqrt(s[0] * s[1]);
}

// The rows of the status bar at the bottom (its state, timings and last
// message change between the screenshots) and a margin.
constexpr int kStatusBarRows = 80;

// Pixels (in the view: right of the panel, above the status bar) that
// differ by more than `tol` in a channel.
struct Diff {
  int count = 0;
  double cx = 0, cy = 0;  // centroid
};
Diff diff(const render::Image& a, const render::Image& b, int x0, int tol = 24) {
  Diff d;
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  for (int y = 0; y < a.height - kStatusBarRows; ++y)
    for (int x = x0; x < a.width; ++x) {
      const auto *p = a.pixel(x, y), *q = b.pixel(x, y);
      if (std::abs(p[0] - q[0]) > tol || std::abs(p[1] - q[1]) > tol || std::abs(p[2] - q[2]) > tol) {
        ++d.count;
        d.cx += x;
        d.cy += y;
      }
    }
  if (d.count) d.cx /= d.count, d.cy /= d.count;
  return d;
}

// Pixels of the highlight colour (1, 0.15, 0.55) in the view.
int highlighted(const render::Image& img, int x0) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = x0; x < img.width; ++x) {
      const auto* p = img.pixel(x, y);
      n += p[0] > 200 && p[1] < 80 && p[2] > 100 && p[2] < 180;
    }
  return n;
}

// Bounding box centre and half width of the non-background pixels of the
// view (between the panel at x0 and the legend at x1).
std::array<double, 3> object_box(const render::Image& img, int x0, int x1) {
  int lo_x = img.width, hi_x = 0, lo_y = img.height, hi_y = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto* p = img.pixel(x, y);
      if (p[0] < 245 || p[1] < 245 || p[2] < 245) {
        lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
        lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
      }
    }
  return {0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y), 0.5 * (hi_x - lo_x)};
}

// tests/data/scripts/NAME with @ASSETS@ and @OUT@ replaced, written into dir.
std::filesystem::path instantiate(const std::string& name, const std::filesystem::path& dir) {
  std::string s = test::file_bytes(test::data_file("scripts/" + name));
  auto replace_all = [&](const std::string& a, const std::string& b) {
    for (std::size_t pos = s.find(a); pos != std::string::npos; pos = s.find(a, pos + b.size())) s.replace(pos, a.size(), b);
  };
  replace_all("@ASSETS@", assets_dir().string());
  replace_all("@OUT@", dir.string());
  const auto out = dir / name;
  std::ofstream(out) << s;
  return out;
}

int run_binary(const std::string& prefix, const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd = prefix + " \"" + ANISURF_BINARY + "\" " + args + " >" + (dir / "stdout.txt").string() + " 2>" +
                          (dir / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The screenshots of panels.anisurf, checked the same way headless and in the window.
void check_panel_screenshots(const std::filesystem::path& dir) {
  auto img = [&](const char* name) {
    const auto p = dir / name;
    REQUIRE_MESSAGE(std::filesystem::exists(p), p.string());
    return render::read_png(p.string());
  };
  const render::Image open = img("00_open.png"), metric_back = img("01_metric_back.png"), paint = img("02_paint.png"),
                      undone = img("03_undone.png"), step = img("04_step.png"), run = img("05_run.png"),
                      select = img("06_select.png"), bezier = img("07_bezier.png"), display = img("08_display.png"),
                      reset = img("09_reset.png");
  const int x0 = 400;  // right of the panel
  const int x1 = open.width - 300;  // left of the legend
  // Back to the file's metric: the same picture as after opening.
  CHECK(diff(open, metric_back, x0).count < 200);
  // The dab at (1, 0, 0) faces the camera (view right): the picture changes
  // around the sphere's centre on the screen, and only there.
  const auto box = object_box(open, x0, x1);
  const Diff dp = diff(open, paint, x0);
  MESSAGE("paint: " << dp.count << " pixels changed around (" << dp.cx << ", " << dp.cy << "); sphere centre (" << box[0]
                    << ", " << box[1] << "), radius " << box[2]);
  CHECK(dp.count > 2000);
  CHECK(std::hypot(dp.cx - box[0], dp.cy - box[1]) < 0.25 * box[2]);
  // Every edit undone: the opening picture again.
  CHECK(diff(open, undone, x0).count < 200);
  // A step and a run change the mesh (the wireframe is off: the colours of
  // the finer mesh differ), the selection shows highlighted triangles.
  CHECK(diff(open, run, x0).count > 5000);
  CHECK(highlighted(run, x0) < 50);
  CHECK(highlighted(select, x0) > 100);
  CHECK(diff(run, bezier, x0).count > 5000);
  CHECK(diff(bezier, display, x0).count > 5000);
  CHECK(diff(open, reset, x0).count > 1000);  // the view changed (iso, glyphs), the mesh is the input again
  (void)step;
  // The saved mesh and metric.
  CHECK(std::filesystem::file_size(dir / "adapted.mesh") > 10000);
  CHECK(std::filesystem::file_size(dir / "adapted.sol") > 10000);
}

// Updates the view until the state it shows is built (in the view's threads); false when it takes over 10 s.
bool update_until_settled(EditorView& ev, EditorSession& s, ViewState& v, render::Scene& scene) {
  ev.update(s, v, scene, 1.6f, 0, 0);
  for (int i = 0; i < 2000 && !ev.settled(s, v); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ev.update(s, v, scene, 1.6f, 0, 0);
  }
  return ev.settled(s, v);
}

}  // namespace

TEST_CASE("editor: control net of a Clough-Tocher patch: 3 quartic subtriangles, inner edges shared") {
  const auto& e = render::control_net_edges();
  CHECK(e.size() == 3 * 30 - 3 * 4);
  for (const auto& [a, b] : e) {
    CHECK(a < b);
    CHECK(b < BezierSurface::kControlPoints);
  }
}

TEST_CASE("editor: undo / redo restore the metric exactly") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  const MetricField m0 = s.metric();
  s.begin_stroke();
  s.dab(Vec3(1, 0, 0), {});
  s.dab(Vec3(0.9, 0.3, 0), Vec3(0, 1, 0));
  s.end_stroke();
  const MetricField m1 = s.metric();
  CHECK(!same(m0, m1));
  s.brush().mode = Brush::Mode::Smooth;
  s.dab(Vec3(0, 1, 0));
  const MetricField m2 = s.metric();
  MetricSettings iso = s.settings();
  iso.source = MetricSettings::Source::Iso;
  iso.iso = 0.3;
  s.set_settings(iso);
  const MetricField m3 = s.metric();
  s.brush().mode = Brush::Mode::Erase;
  s.dab(Vec3(0, 0, 1));  // back towards the iso field: no change expected there
  CHECK(s.undo());
  CHECK(same(s.metric(), m3));
  CHECK(s.undo());
  CHECK(same(s.metric(), m2));
  CHECK(s.settings().source == MetricSettings::Source::Sol);
  CHECK(s.undo());
  CHECK(same(s.metric(), m1));
  CHECK(s.undo());
  CHECK(same(s.metric(), m0));
  CHECK(!s.undo());
  CHECK(s.redo());
  CHECK(same(s.metric(), m1));
  CHECK(s.redo());
  CHECK(same(s.metric(), m2));
  CHECK(s.redo());
  CHECK(same(s.metric(), m3));
  CHECK(s.settings().source == MetricSettings::Source::Iso);
}

TEST_CASE("editor: the brush changes the metric within its radius, towards its size, stretched along the direction") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  const MetricField m0 = s.metric();
  const Vec3 c(1, 0, 0);
  Brush& b = s.brush();
  b.radius = 0.4;
  b.size = 0.01;
  b.stretch = 5;
  b.strength = 1;
  s.dab(c, Vec3(0, 1, 0));
  const SurfaceMesh& m = s.input();
  int inside = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    const double d = norm(m.position(Vertex(v)) - c);
    if (d >= b.radius) {
      CHECK(s.metric()[v].m == m0[v].m);
    } else if (d < 0.05) {
      // At the centre: the target, sizes 0.05 along y and 0.01 across.
      ++inside;
      CHECK(std::sqrt(1 / quad(s.metric()[v], Vec3(0, 1, 0))) == doctest::Approx(0.05).epsilon(0.02));
      CHECK(std::sqrt(1 / quad(s.metric()[v], Vec3(0, 0, 1))) == doctest::Approx(0.01).epsilon(0.02));
      CHECK(tangent_size(s.metric()[v]) < tangent_size(m0[v]));
    }
  }
  CHECK(inside >= 1);
  CHECK(s.predicted_vertices() > 0);
}

TEST_CASE("editor: adaptation pass by pass, timeline, cancel and reset") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  CHECK(s.timeline().size() == 1);
  s.step();
  s.wait();
  auto tl = s.timeline();
  REQUIRE(tl.size() == 2);
  CHECK(tl[1]->has_report);
  CHECK(tl[1]->report.kind == remesh::PassKind::Swap);  // the initial swaps
  s.run(3);
  s.wait();
  tl = s.timeline();
  REQUIRE(tl.size() == 5);
  CHECK(tl[2]->report.kind == remesh::PassKind::Split);
  CHECK(tl[2]->report.splits > 0);
  CHECK(tl[2]->mesh.n_vertices() > tl[1]->mesh.n_vertices());
  // Scrub back and run from there: the timeline is cut after the shown pass.
  s.scrub(2);
  CHECK(s.display().snapshot == tl[2]);
  s.step();
  s.wait();
  CHECK(s.timeline().size() == 4);
  s.run();
  s.wait();
  tl = s.timeline();
  CHECK(tl.back()->schedule.phase == Schedule::Phase::Done);
  CHECK(tl.back()->report.kind == remesh::PassKind::Final);
  CHECK(tl.back()->mesh.validate().ok());
  const Analysis& a = s.analysis();
  MESSAGE("demo adapted: " << tl.size() - 1 << " passes, " << tl.back()->mesh.n_vertices() << " vertices, in band "
                           << 100 * a.in_band_share << "%, q mean " << a.quality_mean);
  CHECK(a.in_band_share > 0.8);
  CHECK(a.quality_mean > 0.8);
  s.reset();
  CHECK(s.timeline().size() == 1);
  CHECK(s.display().snapshot->mesh.n_vertices() == 162);
  // Cancel: back to where the run started, whenever the worker stops.
  s.run(2);
  s.wait();
  REQUIRE(s.timeline().size() == 3);
  s.run();
  s.cancel();
  s.wait();
  CHECK(s.timeline().size() == 3);
  CHECK(s.display().snapshot == s.timeline().back());
  // A metric edit during a run drops the adaptation at once (its worker ends
  // its pass on the side); the next step starts from T_0 with the new metric.
  s.run();
  MetricSettings iso = s.settings();
  iso.source = MetricSettings::Source::Iso;
  iso.iso = 0.25;
  s.set_settings(iso);
  CHECK(!s.running());
  CHECK(s.timeline().size() == 1);
  s.step();
  s.wait();
  REQUIRE(s.timeline().size() == 2);
  CHECK(s.timeline()[1]->metric[0].m == isotropic_metric(0.25).m);
}

TEST_CASE("editor: a histogram bin selects its elements, the worst one is the farthest from the unit") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  const Analysis a = s.analysis();
  int total = 0;
  for (int c : a.quality_histogram) total += c;
  CHECK(total == s.input().n_triangles());
  int bin = 0;
  for (int i = 0; i < kQualityBins; ++i)
    if (a.quality_histogram[i] > 0) bin = i;
  s.select_bin(BinKind::Quality, bin);
  const Selection& sel = s.selection();
  CHECK(static_cast<int>(sel.triangles.size()) == a.quality_histogram[bin]);
  for (std::size_t i = 0; i < a.triangles.size(); ++i)
    if (std::find(sel.triangles.begin(), sel.triangles.end(), a.triangles[i]) != sel.triangles.end()) {
      CHECK(a.quality[i] >= bin / 10.0);
      CHECK(a.quality[i] >= sel.worst_value);
    }
  s.select_bin(BinKind::Length, 3);  // edges [0.71, 0.9): none on the coarse input
  CHECK(s.selection().triangles.empty());
  CHECK_THROWS_WITH_AS(s.select_bin(BinKind::Quality, 10), doctest::Contains("bins 0 to 9"), Error);
}

TEST_CASE("editor: script errors name the file and the line") {
  const auto dir = test::temp_dir("editor_script_errors");
  EditorSession s;
  ViewState v;
  ScriptHost host;
  auto run = [&](const std::string& text) {
    std::ofstream(dir / "bad.anisurf") << "open " << demo_mesh() << " " << demo_sol() << "\n# comment\n\n" << text << "\n";
    for (const auto& l : read_script((dir / "bad.anisurf").string())) execute(l, s, v, host);
  };
  const std::string at = (dir / "bad.anisurf").string() + ":4: ";
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      run(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  CHECK_MESSAGE(error_of("metric iso -1").find(at + "metric iso: H must be > 0") != std::string::npos, error_of("metric iso -1"));
  CHECK_MESSAGE(error_of("metric size 0.1 + foo").find(at + "metric: ") != std::string::npos, error_of("metric size 0.1 + foo"));
  CHECK_MESSAGE(error_of("paint 1 0 0 0.1").find(at + "usage: paint X Y Z RADIUS SIZE") != std::string::npos, error_of("paint 1 0 0 0.1"));
  CHECK_MESSAGE(error_of("select-bin angle 2").find(at + "usage: select-bin length|quality I") != std::string::npos, error_of("select-bin angle 2"));
  CHECK_MESSAGE(error_of("color purple").find(at + "color: expects") != std::string::npos, error_of("color purple"));
  CHECK_MESSAGE(error_of("undo").find(at + "undo: nothing to undo") != std::string::npos, error_of("undo"));
  CHECK_MESSAGE(error_of("lmin 2").find(at + "lmin: the edge length band needs 0 < lmin < lmax") != std::string::npos,
                error_of("lmin 2"));
  CHECK_MESSAGE(error_of("frobnicate").find(at + "unknown command 'frobnicate'") != std::string::npos, error_of("frobnicate"));
  CHECK_MESSAGE(error_of("open /nonexistent/x.mesh").find(at + "open: ") != std::string::npos, error_of("open /nonexistent/x.mesh"));
  // Values out of range are refused on their own line, the metric untouched.
  const MetricField before = s.metric();
  CHECK_MESSAGE(error_of("paint 1 0 0 0.5 1e-308").find(at + "paint: a size of 1e-308 gives no metric") != std::string::npos,
                error_of("paint 1 0 0 0.5 1e-308"));
  CHECK_MESSAGE(error_of("paint 1 0 0 0.5 0.1 1e12 1 0 0").find(at + "paint: the brush gives no metric") != std::string::npos,
                error_of("paint 1 0 0 0.5 0.1 1e12 1 0 0"));
  CHECK(same(s.metric(), before));
  CHECK(!s.in_stroke());
  CHECK_MESSAGE(error_of("paint 1 0 0 0.5 1e999").find(at + "paint: SIZE is out of range") != std::string::npos,
                error_of("paint 1 0 0 0.5 1e999"));
  CHECK_MESSAGE(error_of("hmax -1").find(at + "hmax expects a size > 0, or 0 for none") != std::string::npos, error_of("hmax -1"));
  CHECK_MESSAGE(error_of("max-aniso 0.5").find(at + "max-aniso expects a ratio >= 1") != std::string::npos,
                error_of("max-aniso 0.5"));
  CHECK_MESSAGE(error_of("timeline -1").find(at + "timeline: I must be a whole number >= 0") != std::string::npos,
                error_of("timeline -1"));
  // A failing metric leaves the session as it was.
  CHECK(s.settings().source == MetricSettings::Source::Sol);
  CHECK(!s.can_undo());
}

TEST_CASE("editor: the session's journal replays to the same metric") {
  const auto dir = test::temp_dir("editor_journal");
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  MetricSettings m = s.settings();
  m.hgrad = 1.5;
  s.set_settings(m);
  s.brush().mode = Brush::Mode::Set;
  s.brush().radius = 0.3;
  s.brush().size = 0.02;
  s.brush().stretch = 3;
  s.dab(Vec3(0, 1, 0), Vec3(1, 0, 0));
  s.brush().mode = Brush::Mode::Smooth;
  s.brush().strength = 0.5;
  s.dab(Vec3(0, 0.9, 0.2));
  // A stroke of three dabs, then one undo: the whole stroke goes, in the
  // session and in the replay.
  s.brush().mode = Brush::Mode::Set;
  s.brush().stretch = 1;
  s.begin_stroke();
  for (double x : {-0.2, 0.0, 0.2}) s.dab(Vec3(x, 0, 1));
  s.end_stroke();
  s.undo();
  {
    std::ofstream out(dir / "journal.anisurf");
    for (const auto& l : s.journal()) out << l << "\n";
  }
  EditorSession r;
  ViewState v;
  for (const auto& l : read_script((dir / "journal.anisurf").string())) execute(l, r, v, {});
  REQUIRE(r.metric().size() == s.metric().size());
  double worst = 0;
  for (std::size_t i = 0; i < s.metric().size(); ++i)
    for (int k = 0; k < 6; ++k)
      worst = std::max(worst, std::abs(r.metric()[i].m[k] - s.metric()[i].m[k]) / (std::abs(s.metric()[i].m[k]) + 1.0));
  CHECK(worst < 1e-6);  // the journal prints 9 significant digits
}

TEST_CASE("editor: scripted session of every panel, headless") {
  const auto dir = test::temp_dir("editor_panels_headless");
  const auto script = instantiate("panels.anisurf", dir);
  const int code = run_binary("env -u DISPLAY", "--script " + script.string() + " --headless --size 1280x800", dir);
  INFO(test::file_bytes(dir / "stderr.txt"));
  REQUIRE(code == 0);
  check_panel_screenshots(dir);
}

TEST_CASE("editor: scripted session of every panel, in the window under xvfb-run") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run not installed (apt-get install xvfb xauth)");
    return;
  }
  const auto dir = test::temp_dir("editor_panels_window");
  const auto script = instantiate("panels.anisurf", dir);
  std::ofstream(script, std::ios::app) << "quit\n";
  const int code = run_binary("xvfb-run -a -s \"-screen 0 1280x800x24\"", "--script " + script.string() + " --size 1280x800", dir);
  INFO(test::file_bytes(dir / "stderr.txt"));
  REQUIRE(code == 0);
  check_panel_screenshots(dir);
}

TEST_CASE("shot --bezier: the G1 surface, its control net, the deviation colormap") {
  const auto dir = test::temp_dir("shot_bezier");
  const std::string base = "shot " + demo_mesh() + " --size 640x400 --no-legend ";
  REQUIRE(run_binary("env -u DISPLAY", base + "-o " + (dir / "mesh.png").string(), dir) == 0);
  REQUIRE(run_binary("env -u DISPLAY", base + "--bezier 6 -o " + (dir / "g1.png").string(), dir) == 0);
  REQUIRE(run_binary("env -u DISPLAY", base + "--bezier 6 --control-net -o " + (dir / "net.png").string(), dir) == 0);
  const render::Image mesh = render::read_png((dir / "mesh.png").string()), g1 = render::read_png((dir / "g1.png").string()),
                      net = render::read_png((dir / "net.png").string());
  // The surface is rounder than the polyhedron: its silhouette differs; the
  // net adds green lines (0.10, 0.45, 0.15).
  CHECK(diff(mesh, g1, 0).count > 500);
  auto green = [](const render::Image& img) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const auto* p = img.pixel(x, y);
        n += p[1] > p[0] + 40 && p[1] > p[2] + 40;
      }
    return n;
  };
  CHECK(green(g1) < 50);
  CHECK(green(net) > 2000);
  CHECK(run_binary("", base + "--color deviation -o " + (dir / "x.png").string(), dir) == 2);
  CHECK(test::file_bytes(dir / "stderr.txt").find("--color deviation needs --bezier K") != std::string::npos);
  CHECK(run_binary("", base + "--control-net -o " + (dir / "x.png").string(), dir) == 2);
}

TEST_CASE("editor: command lines") {
  const auto dir = test::temp_dir("editor_cli");
  CHECK(run_binary("", "--script", dir) == 2);
  CHECK(run_binary("", "--script /nonexistent.anisurf --headless", dir) == 1);
  CHECK(test::file_bytes(dir / "stderr.txt").find("/nonexistent.anisurf: cannot read the script") != std::string::npos);
  CHECK(run_binary("", "--help-script", dir) == 0);
  CHECK(test::file_bytes(dir / "stdout.txt").find("select-bin length|quality I") != std::string::npos);
  // Without a display the window fails with a hint (exit code 1).
  CHECK(run_binary("env -u DISPLAY", demo_mesh(), dir) == 1);
  CHECK(test::file_bytes(dir / "stderr.txt").find("no DISPLAY") != std::string::npos);
  // Subcommands still reach the regular command line.
  CHECK(run_binary("", "info " + demo_mesh(), dir) == 0);
}
TEST_CASE("editor: a script's run, anisurf adapt and a library call give the same bytes") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("editor_same_as_cli");
  {
    std::ofstream f(dir / "run.anisurf");
    // The editor uses a loaded metric as given; anisurf adapt grades it by
    // default (hgrad 1.3): asked for here, the same metric; and without
    // the geometry protection (--hausd 0, protect_fraction 0) as the editor.
    f << "open " << mesh << " " << sol << "\nhgrad 1.3\nrun\nsave " << (dir / "editor.mesh").string() << " "
      << (dir / "editor.sol").string() << "\n";
  }
  REQUIRE(run_binary("env -u DISPLAY", "--script " + (dir / "run.anisurf").string() + " --headless", dir) == 0);
  int status = -1;
  test::capture(std::string(ANISURF_BINARY) + " adapt '" + mesh + "' -sol '" + sol + "' --hausd 0 -v 0 -o '" +
                    (dir / "cli.mesh").string() + "'",
                &status);
  REQUIRE(status == 0);
  BuildReport report;
  remesh::AdaptInput input{load_mesh(mesh, &report)};
  remesh::AdaptOptions o;
  o.protect_fraction = 0;
  o.metric.source = MetricRecipe::Source::Given;
  SurfaceMesh with_fields = input.mesh;
  attach_fields(with_fields, read_sol(sol, report.input_vertices), report);
  o.metric.given = metric_from_field(with_fields);
  save_mesh((dir / "library.mesh").string(), remesh::adapt(std::move(input), o).mesh);
  CHECK(test::file_bytes(dir / "editor.mesh") == test::file_bytes(dir / "cli.mesh"));
  CHECK(test::file_bytes(dir / "editor.sol") == test::file_bytes(dir / "cli.sol"));
  CHECK(test::file_bytes(dir / "library.mesh") == test::file_bytes(dir / "cli.mesh"));
}

TEST_CASE("editor: cycles re-derive the metric on the adapted mesh, as anisurf adapt --cycles does") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/square3d.mesh");
  const auto dir = test::temp_dir("editor_cycles");
  const std::string f = "100*x^2+exp(-20*(x-0.5)^2-20*(y-0.5)^2)";
  {
    std::ofstream s(dir / "cycles.anisurf");
    s << "open " << mesh << "\nhgrad 0\nmetric hessian " << f << " 0.01\ncycles 3\nsave "
      << (dir / "editor.mesh").string() << "\n";
  }
  REQUIRE(run_binary("env -u DISPLAY", "--script " + (dir / "cycles.anisurf").string() + " --headless", dir) == 0);
  const std::string log = test::file_bytes(dir / "stderr.txt");
  CHECK(log.find("cycle 2:") != std::string::npos);
  int status = -1;
  const std::string out = test::capture(std::string(ANISURF_BINARY) + " adapt '" + mesh + "' --hessian-of '" + f +
                                            "' --error 0.01 -hgrad -1 --cycles 3 -v 0 -o '" +
                                            (dir / "cli.mesh").string() + "'",
                                        &status);
  REQUIRE(status == 0);
  CHECK(test::file_bytes(dir / "editor.mesh") == test::file_bytes(dir / "cli.mesh"));

  // In process: a cycle needs an adapted mesh shown, and makes it T_0.
  EditorSession s;
  s.open(mesh);
  MetricSettings m = s.settings();
  m.source = MetricSettings::Source::Hessian;
  m.hessian_expr = f;
  m.hessian_error = 0.01;
  s.set_settings(m);
  CHECK_THROWS_AS(s.next_cycle(), Error);
  s.run();
  s.wait();
  const int adapted = s.timeline().back()->mesh.n_vertices();
  CHECK(s.next_cycle() == adapted);
  CHECK(s.cycle() == 1);
  CHECK(s.input().n_vertices() == adapted);
  CHECK(s.input().validate().ok());
  CHECK(s.timeline().size() == 1);  // the new T_0 alone
}

TEST_CASE("editor: the distance colours: T_1's distance to T_G per vertex, after each pass shown, in the legend and the panel") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  ViewState v;
  v.color = "distance";
  EditorView ev;
  render::Scene scene;
  // The view shows a state with its distance once measured (in the session's thread).
  auto update = [&] { CHECK(update_until_settled(ev, s, v, scene)); };
  auto shown_distance = [&]() -> const render::ScalarQuantity* {
    for (const auto& st : scene.surfaces)
      if (st.name == "mesh") return st.active_scalar();
    return nullptr;
  };
  // T_0 is the input itself: 0 everywhere.
  update();
  const render::ScalarQuantity* q = shown_distance();
  REQUIRE(q);
  CHECK(q->name == render::quantity::kDistance);
  REQUIRE(s.distance());
  CHECK(s.distance()->max() < 1e-12);
  for (float x : q->values) CHECK(x < 1e-6f);
  CHECK(q->range_max > 0.0f);  // a usable legend all the same
  // After a run: the mesh shown is T_1, coloured by its own distances.
  s.run();
  s.wait();
  update();
  q = shown_distance();
  REQUIRE(q);
  const SurfaceMesh& t1 = s.display().snapshot->mesh;
  const SurfaceDistance expect = surface_distance(t1, s.geometry_input());
  const auto d = s.distance();
  REQUIRE(d);
  CHECK(d == s.distance());  // kept for the state shown, not measured again
  bool current = false;
  CHECK(s.last_distance(&current) == d);
  CHECK(current);
  CHECK(d->vertices.count == t1.n_vertices());
  CHECK(d->max() == doctest::Approx(expect.max()).epsilon(1e-12));
  CHECK(d->centroids.mean == doctest::Approx(expect.centroids.mean).epsilon(1e-12));
  CHECK(d->max() > 0);
  REQUIRE(q->values.size() == static_cast<std::size_t>(t1.n_vertices()));
  float qmax = 0;
  for (float x : q->values) qmax = std::max(qmax, x);
  CHECK(qmax == doctest::Approx(d->vertices.max).epsilon(1e-6));
  // The colours end at the 98th percentile of the vertex distances.
  std::vector<float> sorted = q->values;
  std::sort(sorted.begin(), sorted.end());
  CHECK(q->range_max == sorted[static_cast<std::size_t>(0.98 * static_cast<double>(sorted.size() - 1))]);
  CHECK(q->range_max <= qmax);
  CHECK(q->percent_of == doctest::Approx(s.input().bbox().diagonal()).epsilon(1e-6));
  CHECK(q->note.find("T_1 to the input T_G at the vertices") != std::string::npos);
  CHECK(q->note.find("max ") != std::string::npos);
  MESSAGE("demo adapted: distance to the input " << d->max() << " (" << d->percent(d->max()) << "% of the diagonal) at a "
                                                 << std::string(distance_sample_name(d->worst_sample())) << ", measured in "
                                                 << s.last_distance_seconds() << " s");
  // Scrubbing back to a pass: measured for that pass.
  s.scrub(1);
  update();
  CHECK(s.last_distance(&current) != d);
  CHECK(current);
  // Another colour: no new measure when the state changes.
  v.color = "size";
  s.scrub(2);
  update();
  s.last_distance(&current);
  CHECK(!current);
}

TEST_CASE("editor: color distance in a script, headless: the legend and the colours of T_1") {
  const auto dir = test::temp_dir("editor_distance_script");
  {
    std::ofstream f(dir / "distance.anisurf");
    f << "open " << demo_mesh() << " " << demo_sol() << "\nwire off\nrun\nscreenshot " << (dir / "size.png").string()
      << "\ncolor distance\nscreenshot " << (dir / "distance.png").string() << "\n";
  }
  const int code = run_binary("env -u DISPLAY", "--script " + (dir / "distance.anisurf").string() + " --headless --size 1280x800", dir);
  INFO(test::file_bytes(dir / "stderr.txt"));
  REQUIRE(code == 0);
  const render::Image size = render::read_png((dir / "size.png").string()),
                      dist = render::read_png((dir / "distance.png").string());
  CHECK(diff(size, dist, 400).count > 5000);
  // Viridis from dark purple (near the input) to yellow (the farthest):
  // both ends appear on the mesh.
  int purple = 0, yellow = 0;
  for (int y = 0; y < dist.height; ++y)
    for (int x = 400; x < dist.width; ++x) {
      const auto* p = dist.pixel(x, y);
      purple += p[2] > p[1] + 40 && p[0] > p[1] + 20;
      yellow += p[0] > 150 && p[1] > 130 && p[2] < 90;
    }
  MESSAGE("distance colours: " << purple << " purple pixels, " << yellow << " yellow ones");
  CHECK(purple > 200);
  CHECK(yellow > 20);
  // The G1 surface hides the mesh the distance colours: refused with a hint.
  {
    std::ofstream f(dir / "bad.anisurf");
    f << "open " << demo_mesh() << "\nbezier 4\ncolor distance\n";
  }
  CHECK(run_binary("env -u DISPLAY", "--script " + (dir / "bad.anisurf").string() + " --headless", dir) == 1);
  CHECK(test::file_bytes(dir / "stderr.txt").find("bad.anisurf:3: color distance: the distance colours the mesh; hide the G1 surface first (bezier off)") !=
        std::string::npos);
  CHECK(run_binary("", "--help-script", dir) == 0);
  CHECK(test::file_bytes(dir / "stdout.txt").find("color size|aniso|length|quality|ref|deviation|distance|fallback|none") != std::string::npos);
}

TEST_CASE("editor: the fallback colours: the vertices pulled to the input, counted from T_1's placements") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  ViewState v;
  v.color = "fallback";
  EditorView ev;
  render::Scene scene;
  // The view builds the structure of a state in its thread: updates until it is shown.
  auto shown = [&]() -> const render::VertexCategories* {
    update_until_settled(ev, s, v, scene);
    for (const auto& st : scene.surfaces)
      if (st.name == "mesh") return st.active_categories();
    return nullptr;
  };
  // The initial state is the input: no placements, said so, drawn in one colour.
  const auto t0 = s.display().snapshot;
  CHECK(!t0->placement.known);
  CHECK(!count_placements(t0->mesh).known);
  CHECK(t0->placement.vertices == t0->mesh.n_vertices());
  const render::VertexCategories* c = shown();
  REQUIRE(c);
  REQUIRE(c->categories.size() == 1);
  CHECK(c->categories[0].label == "input vertices: " + std::to_string(t0->mesh.n_vertices()));
  CHECK(c->note.find("the initial mesh") != std::string::npos);
  for (int x : c->values) CHECK(x == 0);
  // On the coarse demo sphere the G1 surface bulges beyond the input bound:
  // the fallback pulls the new vertices back towards the input.
  s.run();
  s.wait();
  const auto t1 = s.display().snapshot;
  REQUIRE(t1->has_report);
  const PlacementCounts& pc = t1->placement;
  REQUIRE(pc.known);
  // The counts agree with the engine's property of the snapshot's mesh.
  const auto state = t1->mesh.get_vertex_property<std::uint8_t>(remesh::kPlacementProperty);
  REQUIRE(state);
  int n[3] = {0, 0, 0};
  for (Vertex x : t1->mesh.vertices()) {
    REQUIRE(state[x] <= 2);
    ++n[state[x]];
  }
  CHECK(pc.off_surface == n[0]);
  CHECK(pc.on_surface == n[1]);
  CHECK(pc.pulled == n[2]);
  CHECK(pc.vertices == t1->mesh.n_vertices());
  CHECK(pc.on_surface + pc.pulled + pc.off_surface == pc.vertices);
  CHECK(pc.pulled > 0);
  CHECK(pc.percent(VertexPlacement::Pulled) == doctest::Approx(100.0 * pc.pulled / pc.vertices));
  MESSAGE("demo adapted: " << pc.pulled << " vertices pulled to the input, " << pc.off_surface << " off the surface, "
                           << pc.on_surface << " on the G1 surface, of " << pc.vertices);
  // The colours: each drawn vertex in its placement's category, the counts in the legend.
  c = shown();
  REQUIRE(c);
  REQUIRE(c->categories.size() == 3);
  char pulled_row[96];
  std::snprintf(pulled_row, sizeof pulled_row, "pulled to the input: %d vertices (%.1f%%)", pc.pulled,
                pc.percent(VertexPlacement::Pulled));
  CHECK(c->categories[1].label == pulled_row);
  CHECK(c->categories[0].label.rfind("on the G1 surface: " + std::to_string(pc.on_surface) + " ", 0) == 0);
  CHECK(c->categories[2].label.rfind("off the surface: " + std::to_string(pc.off_surface) + " ", 0) == 0);
  int drawn[3] = {0, 0, 0};
  REQUIRE(c->values.size() == static_cast<std::size_t>(t1->mesh.n_vertices()));
  for (int x : c->values) {
    REQUIRE((x >= 0 && x <= 2));
    ++drawn[x];
  }
  CHECK(drawn[0] == pc.on_surface);
  CHECK(drawn[1] == pc.pulled);
  CHECK(drawn[2] == pc.off_surface);
  // Every pass records its placements; the vertex under the mouse tells its own.
  for (const auto& snap : s.timeline()) CHECK(snap->placement.known == snap->has_report);
  for (Vertex x : t1->mesh.vertices())
    CHECK(vertex_placement(t1->mesh, x) == (state[x] == 2 ? VertexPlacement::Pulled
                                            : state[x] == 0 ? VertexPlacement::OffSurface
                                                            : VertexPlacement::OnSurface));
  // A cycle makes T_1 the new T_0: its initial state has no placements (not the last run's).
  s.next_cycle();
  CHECK(!s.display().snapshot->placement.known);
  CHECK(!s.input().get_vertex_property<std::uint8_t>(remesh::kPlacementProperty));
  c = shown();
  REQUIRE(c);
  CHECK(c->categories.size() == 1);
}

TEST_CASE("editor: color fallback in a script, headless: the pulled vertices in red, the legend's counts") {
  const auto dir = test::temp_dir("editor_fallback_script");
  {
    std::ofstream f(dir / "fallback.anisurf");
    f << "open " << demo_mesh() << " " << demo_sol() << "\nwire off\ntouched off\ncolor fallback\nscreenshot "
      << (dir / "initial.png").string() << "\nrun\ncolor size\nscreenshot " << (dir / "size.png").string()
      << "\ncolor fallback\nscreenshot " << (dir / "fallback.png").string() << "\n";
  }
  const int code = run_binary("env -u DISPLAY", "--script " + (dir / "fallback.anisurf").string() + " --headless --size 1280x800", dir);
  INFO(test::file_bytes(dir / "stderr.txt"));
  REQUIRE(code == 0);
  const render::Image initial = render::read_png((dir / "initial.png").string()),
                      size = render::read_png((dir / "size.png").string()),
                      fallback = render::read_png((dir / "fallback.png").string());
  // Pixels of the pulled colour (0.88, 0.12, 0.10), lit, in the view (right of
  // the panel, left of the legend's swatches).
  auto red = [](const render::Image& img) {
    int count = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 400; x < img.width - 360; ++x) {
        const auto* p = img.pixel(x, y);
        count += p[0] > 120 && p[1] < 0.45 * p[0] && p[2] < 0.45 * p[0];
      }
    return count;
  };
  const int r_initial = red(initial), r_size = red(size), r_fallback = red(fallback);
  MESSAGE("red pixels: initial " << r_initial << ", size colours " << r_size << ", fallback colours " << r_fallback);
  CHECK(r_initial < 50);  // no placements before a pass: grey
  CHECK(r_size < 50);
  CHECK(r_fallback > 20000);
  CHECK(diff(size, fallback, 400).count > 5000);
  // The G1 surface hides the mesh the placements colour: refused with a hint.
  {
    std::ofstream f(dir / "bad.anisurf");
    f << "open " << demo_mesh() << "\nbezier 4\ncolor fallback\n";
  }
  CHECK(run_binary("env -u DISPLAY", "--script " + (dir / "bad.anisurf").string() + " --headless", dir) == 1);
  CHECK(test::file_bytes(dir / "stderr.txt").find("bad.anisurf:3: color fallback: the placements colour the mesh; hide the G1 surface first (bezier off)") !=
        std::string::npos);
}

TEST_CASE("editor: a .vtu or .msh with its metric inside opens with that metric, and recomputes it from the file") {
  const auto dir = anisurf::test::temp_dir("editor_embedded_metric");
  EditorSession ref;
  ref.open(demo_mesh(), demo_sol());
  for (const char* name : {"demo.vtu", "demo.msh"}) {
    CAPTURE(name);
    const std::string path = (dir / name).string();
    BuildReport report;
    SurfaceMesh with_sol = load_mesh(demo_mesh(), &report);
    attach_fields(with_sol, read_sol(demo_sol(), report.input_vertices), report);
    save_mesh(path, with_sol);
    EditorSession s;
    s.open(path);
    CHECK(s.settings().source == MetricSettings::Source::Sol);
    CHECK(s.predicted_vertices() == doctest::Approx(ref.predicted_vertices()).epsilon(1e-9));
    // A change of the gradation reads the metric again, from the file itself.
    MetricSettings changed = s.settings();
    changed.hgrad = 2.0;
    s.set_settings(changed);
    CHECK(s.predicted_vertices() > 0);
  }
}

TEST_CASE("editor: defaults at the model's scale: the iso size keeps the input's density, the brush follows the diagonal") {
  const auto dir = test::temp_dir("editor_scale");
  SurfaceMesh mesh = load_mesh(demo_mesh());
  const std::string unit_path = (dir / "unit.mesh").string(), big_path = (dir / "big.mesh").string();
  save_mesh(unit_path, mesh);
  for (Vertex v : mesh.vertices()) mesh.position(v) = 1000.0 * mesh.position(v);
  save_mesh(big_path, mesh);

  EditorSession unit, big;
  unit.open(unit_path);
  big.open(big_path);
  for (EditorSession* s : {&unit, &big}) {
    REQUIRE(s->settings().source == MetricSettings::Source::Iso);
    // Adapting right after opening keeps about the input's vertex count.
    const double n = s->input().n_vertices();
    CHECK(s->predicted_vertices() == doctest::Approx(n).epsilon(0.05));
    const BBox b = s->input().bbox();
    CHECK(s->brush().radius == doctest::Approx(norm(b.hi - b.lo) / 10));
    CHECK(s->brush().size == doctest::Approx(0.5 * s->settings().iso));
  }
  CHECK(big.settings().iso == doctest::Approx(1000 * unit.settings().iso).epsilon(1e-6));
  MESSAGE("demo: iso " << unit.settings().iso << " for " << unit.input().n_vertices() << " vertices, predicted "
                       << unit.predicted_vertices());
}

TEST_CASE("editor: the size legend follows painted values beyond its range, and keeps its ends otherwise") {
  EditorSession s;
  s.open(demo_mesh(), demo_sol());
  ViewState v;
  v.color = render::quantity::kSize;
  EditorView ev;
  render::Scene scene;
  auto update = [&] { REQUIRE(update_until_settled(ev, s, v, scene)); };
  auto size_range = [&]() -> std::array<float, 2> {
    for (const auto& st : scene.surfaces)
      if (st.name == "mesh")
        for (const auto& q : st.scalars)
          if (q.name == render::quantity::kSize) return {q.range_min, q.range_max};
    FAIL("no size quantity shown");
    return {0, 0};
  };
  update();
  const std::array<float, 2> r0 = size_range();
  REQUIRE(r0[0] > 0);
  // A dab of a size inside the range: the ends stay (the colours elsewhere keep their meaning).
  Brush& b = s.brush();
  b.radius = 0.3;
  b.stretch = 1;
  b.strength = 1;
  b.size = std::sqrt(static_cast<double>(r0[0]) * r0[1]);
  s.dab(Vec3(1, 0, 0));
  s.end_stroke();
  update();
  CHECK(size_range()[0] == r0[0]);
  CHECK(size_range()[1] == r0[1]);
  // Dabs far above and below it: the legend's ends reach the painted sizes.
  b.size = 4.0 * r0[1];
  s.dab(Vec3(-1, 0, 0));
  s.end_stroke();
  update();
  CHECK(size_range()[1] >= 0.95f * static_cast<float>(b.size));
  b.size = 0.25 * r0[0];
  s.dab(Vec3(0, 1, 0));
  s.end_stroke();
  update();
  CHECK(size_range()[0] <= 1.05f * static_cast<float>(b.size));
  CHECK(size_range()[1] >= 0.95f * static_cast<float>(4.0 * r0[1]));
  // Every dab undone: the first ends again (the first picture back).
  while (s.can_undo()) REQUIRE(s.undo());
  update();
  CHECK(size_range()[0] == r0[0]);
  CHECK(size_range()[1] == r0[1]);
}

#endif  // ANISURF_WITH_GL
