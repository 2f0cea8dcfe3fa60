// The editor never freezes: the metric is built in the background (an
// apply installs it once built, a preview only counts its vertices, a newer
// request supersedes an older one, undo restores without building again),
// the G1 surface is built in the background by the view, the control net is
// capped to the patches nearest the view's centre; and, in the window under
// Xvfb on the Falcon (../shared), the slowest frame while a curvature metric
// is built, the G1 surface is shown and a pass runs.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "editor/editor_view.h"
#include "editor/session.h"
#include "geometry/normals.h"
#include "io/mesh_io.h"
#include "render/bezier_structure.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;
namespace fs = std::filesystem;

namespace {

bool same(const MetricField& a, const MetricField& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].m != b[i].m) return false;
  return true;
}

// Polls the session (as the window does every frame) until its metric
// builds are done; false after `seconds`.
bool wait_metric(EditorSession& s, double seconds = 120) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (s.metric_building()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    s.poll();
  }
  return true;
}

int count_lines(const std::vector<std::string>& journal, const std::string& line) {
  return static_cast<int>(std::count(journal.begin(), journal.end(), line));
}

}  // namespace

TEST_CASE("editor metric in the background: an apply installs once built, a preview only counts, the newest request wins") {
  EditorSession s;
  s.open(test::asset_file("demo.mesh"));
  const MetricSettings start = s.settings();
  const MetricField start_metric = s.metric();
  MetricSettings a = start, b = start, c = start;
  a.source = b.source = MetricSettings::Source::Iso;
  a.iso = 0.3;
  b.iso = 0.15;
  c.source = MetricSettings::Source::Curvature;
  c.hausd = 0.005;

  // A preview builds in the background and installs nothing.
  s.request_metric(a, false);
  CHECK(s.settings() == start);
  REQUIRE(wait_metric(s));
  CHECK(s.settings() == start);
  CHECK(same(s.metric(), start_metric));
  REQUIRE(s.preview(a).has_value());
  CHECK(*s.preview(a) == doctest::Approx(s.predict_vertices(a)));
  CHECK_FALSE(s.preview(b).has_value());

  // Applying the settings just previewed installs the metric built for it at once.
  s.request_metric(a, true);
  CHECK_FALSE(s.metric_building());
  CHECK(s.settings() == a);
  const MetricField metric_a = s.metric();
  CHECK(count_lines(s.journal(), "metric iso 0.3") == 1);

  // Two applies in a row: the call returns before anything is installed
  // (the view keeps the current metric), and only the newest one is
  // installed: one undoable edit, one journal line.
  s.request_metric(c, true);
  CHECK(s.settings() == a);
  s.request_metric(b, true);
  CHECK(s.settings() == a);
  CHECK(s.metric_building());
  REQUIRE(wait_metric(s));
  CHECK(s.settings() == b);
  CHECK(s.apply_error().empty());
  CHECK(count_lines(s.journal(), "metric curvature 0.005") == 0);
  CHECK(count_lines(s.journal(), "metric iso 0.15") == 1);
  REQUIRE(s.undo());
  CHECK(s.settings() == a);
  CHECK(same(s.metric(), metric_a));
  CHECK(same(s.base_metric(), metric_a));
  REQUIRE(s.redo());
  CHECK(s.settings() == b);

  // A metric that cannot be built: the error, the settings unchanged.
  MetricSettings bad = b;
  bad.source = MetricSettings::Source::Size;
  bad.size_expr = "0.1 + nosuchfunction(x)";
  s.request_metric(bad, true);
  REQUIRE(wait_metric(s));
  CHECK(s.settings() == b);
  CHECK_FALSE(s.apply_error().empty());
  CHECK_FALSE(s.metric_error(bad).empty());
  CHECK_FALSE(s.preview(bad).has_value());

  // Opening a mesh drops what was built for the previous one.
  s.request_metric(a, false);
  s.open(test::asset_file("demo.mesh"));
  CHECK_FALSE(s.metric_building());
  const bool stale_preview = s.preview(a).has_value() && !(s.settings() == a);
  CHECK_FALSE(stale_preview);
}

TEST_CASE("editor: the control net of at most N patches, the nearest to a centre or every n-th") {
  const SurfaceMesh m = load_mesh(test::asset_file("demo.mesh"));
  const BezierSurface surface(m, compute_frames(m));
  const auto edges = render::control_net_edges().size();
  auto net_points = [](const render::SurfaceStructure& s, const char* name) -> std::vector<glm::vec3> {
    for (const auto& c : s.curves)
      if (c.name == name) return c.points;
    for (const auto& mk : s.markers)
      if (mk.name == name) return mk.positions;
    return {};
  };
  render::BezierStructureOptions o;
  o.k = 2;
  render::BezierNetInfo all;
  const auto full = render::make_bezier_structure(m, surface, "g1", o, &all);
  CHECK(all.patches == m.n_triangles());
  CHECK(all.shown == m.n_triangles());
  CHECK(net_points(full, "control net").size() == 2 * edges * static_cast<std::size_t>(m.n_triangles()));

  const int n = 12;
  REQUIRE(m.n_triangles() > 4 * n);
  o.net_max_patches = n;
  o.net_centre = glm::vec3(1.0f, 0.0f, 0.0f);  // on the unit sphere of the demo
  render::BezierNetInfo near;
  const auto capped = render::make_bezier_structure(m, surface, "g1", o, &near);
  CHECK(near.shown == n);
  CHECK(near.patches == m.n_triangles());
  const auto pts = net_points(capped, "control net");
  CHECK(pts.size() == 2 * edges * n);
  CHECK(net_points(capped, "control points").size() == static_cast<std::size_t>(n * (BezierSurface::kControlPoints - 3)));
  // The patches shown are the ones around the centre: no net point on the far side.
  float farthest = 0;
  for (const auto& p : pts) farthest = std::max(farthest, glm::length(p - *o.net_centre));
  CHECK(farthest < 0.7f);
  // The surface itself is whole.
  CHECK(capped.geometry.triangles.size() == full.geometry.triangles.size());

  o.net_centre.reset();  // every n-th patch: spread over the sphere
  render::BezierNetInfo spread;
  const auto strided = render::make_bezier_structure(m, surface, "g1", o, &spread);
  CHECK(spread.shown == n);
  float spread_far = 0;
  for (const auto& p : net_points(strided, "control net")) spread_far = std::max(spread_far, glm::length(p - glm::vec3(1, 0, 0)));
  CHECK(spread_far > 1.5f);
}

TEST_CASE("editor view: the G1 surface is built in the background, the view is settled once it is shown") {
  EditorSession s;
  s.open(test::asset_file("demo.mesh"));
  ViewState v;
  v.bezier = 3;
  v.control_net = true;
  render::Scene scene;
  EditorView ev;
  ev.update(s, v, scene, 1.6f, 0, 0);
  // The first update starts the build and returns: the mesh is drawn meanwhile.
  CHECK_FALSE(ev.bezier_current(v));
  CHECK_FALSE(ev.settled(s, v));
  bool found = false;
  for (const auto& st : scene.surfaces) found |= st.name == "G1 surface";
  CHECK_FALSE(found);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!ev.bezier_current(v) && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ev.update(s, v, scene, 1.6f, 0, 0);
  }
  REQUIRE(ev.bezier_current(v));
  CHECK(ev.settled(s, v));
  CHECK(ev.bezier_k() == 3);
  CHECK(ev.net_info().patches == s.input().n_triangles());
  CHECK(ev.net_info().shown == std::min(EditorView::kNetMaxPatches, s.input().n_triangles()));
  found = false;
  for (const auto& st : scene.surfaces) found |= st.name == "G1 surface" && !st.geometry.triangles.empty();
  CHECK(found);
}

TEST_CASE("editor window on the Falcon: the slowest frame while a curvature metric is built, the G1 surface shown and a pass runs") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run not installed (apt-get install xvfb xauth)");
    return;
  }
  ANISURF_REQUIRE_SHARED(falcon, "meshes/falcon.mesh");
  const auto dir = test::temp_dir("editor_frames_falcon");
  // First frames with nothing to do (the cost of drawing the Falcon on this
  // machine), then the actions of the issue: choose a curvature metric,
  // edit it (a typed bound), show the G1 surface with its control net,
  // step. Each line waits for the background work of the one before (the
  // script's rule); the frames of all of it are measured, the opening is not.
  const auto script = dir / "frames.anisurf";
  {
    std::ofstream out(script);
    out << "open " << falcon << "\n"
        << "frame-stats reset\n";
    for (int i = 0; i < 15; ++i) out << "view iso\n";
    out << "frame-stats\n"
        << "frame-stats reset\n"
        << "metric curvature 0.01\n"
        << "hmin 0.002\n"
        << "bezier 4\n"
        << "control-net on\n"
        << "step\n"
        << "frame-stats\n"
        << "quit\n";
  }
  const std::string cmd = "XDG_STATE_HOME='" + (dir / "state").string() + "' xvfb-run -a -s '-screen 0 1280x800x24' '" +
                          ANISURF_BINARY + "' --script '" + script.string() + "' --size 1280x800 >'" +
                          (dir / "stdout.txt").string() + "' 2>'" + (dir / "stderr.txt").string() + "'";
  const std::regex totals(R"(frame stats: (\d+) frames, mean ([0-9.]+) ms, slowest ([0-9.]+) ms)");
  std::string err;
  std::vector<std::smatch> found;
  // A second attempt when the window closed before the script's end (seen
  // once among the parallel tests of CI, with exit status 0 and the first
  // figures printed): the figures of a whole run are what is checked.
  for (int attempt = 1; attempt <= 2; ++attempt) {
    const int status = std::system(cmd.c_str());
    err = test::file_bytes(dir / "stderr.txt");
    INFO(err);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    found.clear();
    for (auto it = std::sregex_iterator(err.begin(), err.end(), totals); it != std::sregex_iterator(); ++it)
      found.push_back(*it);
    if (found.size() == 2) break;
    MESSAGE("attempt " << attempt << ": the window's run ended early:\n" << err);
  }
  INFO(err);
  REQUIRE(found.size() == 2);
  const double idle_mean = std::stod(found[0][2]);
  const int frames = std::stoi(found[1][1]);
  const double slowest = std::stod(found[1][3]);
  MESSAGE("falcon, nothing to do: " << found[0][1] << " frames, mean " << idle_mean << " ms, slowest " << found[0][3] << " ms");
  MESSAGE("falcon, the actions: " << frames << " frames, mean " << found[1][2] << " ms, slowest " << slowest << " ms");
  // The pass's own duration (a pass shorter than about two frames may run
  // between two of them: nothing to see then).
  std::smatch pass_time;
  const bool timed = std::regex_search(err, pass_time, std::regex(R"(its pass ([0-9.]+) s)"));
  const double pass_ms = timed ? 1000 * std::stod(pass_time[1].str()) : INFINITY;
  const double mean_ms = std::stod(found[1][2]);
  for (const char* what : {"a metric is built", "a pass runs", "the G1 surface is built"}) {
    std::smatch w;
    const bool seen = std::regex_search(err, w, std::regex(std::string("while ") + what + R"(: (\d+) frames, slowest ([0-9.]+) ms)"));
    const bool too_short = std::string(what) == "a pass runs" &&
                           (pass_ms < 2 * mean_ms || err.find("adaptation: started and done within one frame") != std::string::npos);
    CHECK_MESSAGE((seen || too_short), "no frame drawn while " << what);
    const std::string line = seen ? std::string("while ") + what + ": " + w[1].str() + " frames, slowest " + w[2].str() + " ms" : "";
    if (seen) MESSAGE(line);
  }
  std::smatch first;
  if (std::regex_search(err, first, std::regex(R"(first pass on screen ([0-9.]+) s[^\n]*)")))
    MESSAGE(first[0].str());
  const std::regex parts(R"(the slowest frame: [^\n]*)");
  for (auto it = std::sregex_iterator(err.begin(), err.end(), parts); it != std::sregex_iterator(); ++it) {
    const std::string line = it->str();
    MESSAGE(line);
  }
  // The acceptance target is 100 ms on a quiet machine. Here the bound is
  // 400 ms, or 3 times the mean frame with nothing to do when the machine is
  // so loaded that drawing alone takes longer, or 400 ms per runnable thread
  // per core (the load average: frames with nothing to do keep their picture
  // and no longer measure the load): it still catches a freeze (the metric
  // built on the window's thread was a frame of 6 s on a quiet machine, the
  // full control net frames of several seconds).
  double load = 0;
  getloadavg(&load, 1);
  const double load_per_core = load / std::max(1u, std::thread::hardware_concurrency());
  MESSAGE("load average " << load << ", " << load_per_core << " per core");
  CHECK(frames > 10);
  CHECK(slowest < std::max({400.0, 3 * idle_mean, 400.0 * load_per_core}));
}

#endif
