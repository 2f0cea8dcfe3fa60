// The editor's work protection: autosaves (one file per launch, never
// another launch's, listed newest first, pruned, write errors reported),
// restoring an autosave without its saves, the overwrite check and the
// default save paths, the Metric panel's draft (a typed value survives the
// field losing focus), a loaded metric used as given and features read back
// from a saved .mesh; and, in the window under Xvfb, a launch that leaves an
// earlier session's autosave unchanged and offers it.
#ifdef ANISURF_WITH_GL
#include <doctest/doctest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "editor/autosave.h"
#include "editor/panels.h"
#include "editor/script.h"
#include "editor/session.h"
#include "io/mesh_io.h"
#include "metric/metric_field.h"
#include "metric/surface_metric.h"
#include "test_geometry_util.h"
#include "test_util.h"

using namespace anisurf;
using namespace anisurf::editor;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kEdited = {"open a.mesh", "metric iso 0.2", "step"};

// The features of a mesh as sets of positions: ridge edges (both ends,
// ordered) and corners.
struct FeatureSets {
  std::set<std::array<double, 6>> ridges;
  std::set<std::array<double, 3>> corners;
};
FeatureSets feature_sets(const SurfaceMesh& m) {
  FeatureSets f;
  for (Corner c : m.edges())
    if (m.has_tag(c, kRidge)) {
      Vec3 a = m.position(m.edge_from(c)), b = m.position(m.edge_to(c));
      std::array<double, 3> x{a.x, a.y, a.z}, y{b.x, b.y, b.z};
      if (y < x) std::swap(x, y);
      f.ridges.insert({x[0], x[1], x[2], y[0], y[1], y[2]});
    }
  for (Vertex v : m.vertices())
    if (m.has_tag(v, kCorner)) f.corners.insert({m.position(v).x, m.position(v).y, m.position(v).z});
  return f;
}

// The unit cube with only its top face's four edges listed as Ridges and its
// four top vertices as Corners (the other eight edges are as sharp: a
// detection would tag them).
std::string write_cube_with_listed_features(const fs::path& dir) {
  MeshData d = test::cube();
  d.edges = {{4, 5}, {5, 7}, {7, 6}, {6, 4}};
  d.ridges = {0, 1, 2, 3};
  d.corners = {4, 5, 6, 7};
  const std::string path = (dir / "cube_listed.mesh").string();
  write_mesh_data(path, d);
  return path;
}

}  // namespace

TEST_CASE("editor autosave: names by input, start time and process, only these are pruned") {
  const std::time_t t = 1764648192;  // a fixed instant; the name shows it in local time
  const std::string name = autosave_name("/data/my bunny.off", t, 4711);
  CHECK(name.rfind("my_bunny-", 0) == 0);
  CHECK(name.size() == std::string("my_bunny-YYYYmmdd-HHMMSS-4711.anisurf").size());
  CHECK(name.substr(name.size() - 13) == "-4711.anisurf");
  CHECK(is_autosave_name(name));
  CHECK(is_autosave_name("bunny-20261202-040312-4711-2.anisurf"));
  CHECK(autosave_name("", t, 1).rfind("session-", 0) == 0);
  CHECK_FALSE(is_autosave_name("autosave.anisurf"));
  CHECK_FALSE(is_autosave_name("demo.anisurf"));
  CHECK_FALSE(is_autosave_name("bunny-20261202-040312-4711.anisurf.tmp-12"));
  CHECK_FALSE(is_autosave_name("bunny-2026120-040312-4711.anisurf"));
  CHECK(journal_has_edits(kEdited));
  CHECK_FALSE(journal_has_edits({"open a.mesh", "save a.mesh", "# comment"}));
}

TEST_CASE("editor autosave: each launch writes its own file, an earlier launch's file never changes") {
  const auto dir = test::temp_dir("editor_autosave_launches");
  const std::time_t t = std::time(nullptr);
  Autosave first(dir.string(), t, 100);
  CHECK_FALSE(first.write({"open a.mesh"}));  // nothing worth keeping yet: no file
  CHECK(first.path().empty());
  CHECK(fs::is_empty(dir));
  REQUIRE(first.write(kEdited));
  const std::string first_bytes = test::file_bytes(first.path());
  CHECK(first_bytes.find("metric iso 0.2\nstep\n") != std::string::npos);
  CHECK_FALSE(first.write(kEdited));  // unchanged journal: not written again

  // A second launch on the same input in the same second, even with the
  // same process id (a name that is taken): another file.
  for (long pid : {200L, 100L}) {
    Autosave later(dir.string(), t, pid);
    REQUIRE(later.write({"open a.mesh", "metric iso 0.3", "run"}));
    CHECK(later.path() != first.path());
    CHECK(later.write({"open a.mesh", "metric iso 0.3", "run", "undo"}));
    CHECK(test::file_bytes(first.path()) == first_bytes);
  }
  // The first launch goes on writing its own file only.
  REQUIRE(first.write({"open a.mesh", "metric iso 0.2", "step", "reset"}));
  CHECK(test::file_bytes(first.path()).find("reset\n") != std::string::npos);
  const auto listed = list_autosaves(dir.string());
  REQUIRE(listed.size() == 3);
  CHECK(listed.front().path == first.path());  // newest first
  CHECK(listed.front().input == "a.mesh");
  CHECK(listed.front().edits == 3);
  CHECK(listed.front().unsaved == 3);
  CHECK(list_autosaves(dir.string(), first.path()).size() == 2);
  // No temporary file left behind.
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().extension() == ".anisurf");
}

TEST_CASE("editor autosave: a write error is reported, and the next write works once it is fixed") {
  const auto dir = test::temp_dir("editor_autosave_error");
  const fs::path blocked = dir / "state";
  std::ofstream(blocked) << "a file where the autosave directory should be\n";
  Autosave a(blocked.string(), std::time(nullptr), 1);
  try {
    a.write(kEdited);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("autosave") != std::string::npos);
    CHECK(std::string(e.what()).find(blocked.string()) != std::string::npos);
  }
  CHECK(a.path().empty());
  fs::remove(blocked);
  CHECK(a.write(kEdited));
  CHECK(fs::exists(a.path()));
  // A directory that refuses the content (read-only) after the name was taken.
  if (::geteuid() != 0) {
    fs::permissions(blocked, fs::perms::owner_read | fs::perms::owner_exec);
    CHECK_THROWS_AS(a.write({"open a.mesh", "metric iso 0.2", "run"}), Error);
    fs::permissions(blocked, fs::perms::owner_all);
  }
}

TEST_CASE("editor autosave: the oldest beyond the newest N are pruned, other files are kept") {
  const auto dir = test::temp_dir("editor_autosave_prune");
  std::vector<std::string> paths;
  const auto now = fs::file_time_type::clock::now();
  for (int i = 0; i < 25; ++i) {
    Autosave a(dir.string(), std::time(nullptr), 1000 + i);
    REQUIRE(a.write(kEdited));
    fs::last_write_time(a.path(), now - std::chrono::minutes(100 - i));  // i = 24 is the newest
    paths.push_back(a.path());
  }
  std::ofstream(dir / "demo.anisurf") << "open a.mesh\nstep\n";  // not an autosave name
  fs::last_write_time(dir / "demo.anisurf", now - std::chrono::hours(100));
  CHECK(prune_autosaves(dir.string(), 20, paths[0]) == 4);
  CHECK(fs::exists(paths[0]));  // the running session's own file stays
  for (int i = 1; i <= 4; ++i) CHECK_FALSE(fs::exists(paths[i]));
  for (int i = 5; i < 25; ++i) CHECK(fs::exists(paths[i]));
  CHECK(fs::exists(dir / "demo.anisurf"));
  const auto listed = list_autosaves(dir.string());
  REQUIRE(listed.size() == 22);
  CHECK(listed.front().path == paths[24]);
}

TEST_CASE("editor autosave: a restore replays the edits, not the saves") {
  const auto dir = test::temp_dir("editor_autosave_restore");
  const std::string saved = (dir / "saved.mesh").string(), saved_sol = (dir / "saved.sol").string();
  EditorSession s;
  s.open(test::asset_file("demo.mesh"));
  MetricSettings m = s.settings();
  m.iso = 0.3;
  s.set_settings(m);
  s.brush().radius = 0.4;
  s.brush().size = 0.05;
  s.dab(Vec3(1, 0, 0));
  s.save(saved, saved_sol);
  s.dab(Vec3(0, 1, 0));
  Autosave a(dir.string(), std::time(nullptr), 1);
  REQUIRE(a.write(s.journal()));
  CHECK(test::file_bytes(a.path()).find("save " + saved) != std::string::npos);
  {
    const auto listed = list_autosaves(dir.string());
    REQUIRE(listed.size() == 1);
    CHECK(listed[0].unsaved == 1);  // the dab after the save
    CHECK(listed[0].describe().find("(1 unsaved)") != std::string::npos);
    Autosave saved_session(dir.string(), std::time(nullptr), 2);
    REQUIRE(saved_session.write({"open a.mesh", "step", "save b.mesh"}));
    const auto all = list_autosaves(dir.string(), a.path());
    REQUIRE(all.size() == 1);
    CHECK(all[0].unsaved == 0);
    CHECK(all[0].describe().find("(all saved)") != std::string::npos);
    fs::remove(saved_session.path());
  }
  // Another program changed the saved files since: a restore leaves them.
  std::ofstream(saved) << "changed since\n";
  fs::remove(saved_sol);
  int skipped = 0;
  const auto lines = restorable_lines(a.path(), &skipped);
  CHECK(skipped == 1);
  for (const auto& l : lines) CHECK(l.words[0] != "save");
  EditorSession r;
  ViewState v;
  CHECK(restore_autosave(a.path(), r, v) == 1);
  CHECK(test::file_bytes(saved) == "changed since\n");
  CHECK_FALSE(fs::exists(saved_sol));
  REQUIRE(r.metric().size() == s.metric().size());
  double worst = 0;
  for (std::size_t i = 0; i < s.metric().size(); ++i)
    for (int k = 0; k < 6; ++k)
      worst = std::max(worst, std::abs(r.metric()[i].m[k] - s.metric()[i].m[k]) / (std::abs(s.metric()[i].m[k]) + 1.0));
  CHECK(worst < 1e-6);
  CHECK(r.dirty());  // the restored edits are unsaved work
  // Not a session: refused with the file's name.
  std::ofstream(dir / "bad.anisurf") << "step\n";
  EditorSession b;
  CHECK_THROWS_WITH_AS(restore_autosave((dir / "bad.anisurf").string(), b, v),
                       doctest::Contains("not an editor session"), Error);
}

TEST_CASE("editor save: default paths beside the opened file, existing files the session did not write are reported") {
  const auto dir = test::temp_dir("editor_save_paths");
  CHECK(default_save_mesh((dir / "bunny.off").string()) == (dir / "bunny.adapted.mesh").string());
  CHECK(default_save_sol((dir / "bunny.off").string()) == (dir / "bunny.adapted.sol").string());
  CHECK(default_save_mesh("rel/x.mesh") == (fs::current_path() / "rel" / "x.adapted.mesh").lexically_normal().string());
  fs::copy_file(test::asset_file("demo.mesh"), dir / "demo.mesh");
  fs::copy_file(test::asset_file("demo.sol"), dir / "demo.sol");
  EditorSession s;
  s.open((dir / "demo.mesh").string());
  const std::string out = default_save_mesh(s.mesh_path()), out_sol = default_save_sol(s.mesh_path());
  CHECK(s.would_overwrite(out, out_sol).empty());
  // The opened file itself, and a file another program made.
  CHECK(s.would_overwrite((dir / "demo.mesh").string()) == std::vector<std::string>{(dir / "demo.mesh").string()});
  std::ofstream(out_sol) << "made elsewhere\n";
  CHECK(s.would_overwrite(out, out_sol) == std::vector<std::string>{out_sol});
  // Once this session wrote them, saving again does not ask.
  s.save(out, out_sol);
  CHECK(s.would_overwrite(out, out_sol).empty());
  CHECK(s.would_overwrite(dir.string() + "/./demo.adapted.mesh").empty());
  // Another mesh opened: the files are an earlier session's now (the issue's
  // case: saving after opening another mesh replaced the earlier file).
  s.open((dir / "demo.mesh").string(), (dir / "demo.sol").string());
  CHECK(s.would_overwrite(out, out_sol) == std::vector<std::string>{out, out_sol});
  // A save error names the file and leaves nothing half written.
  CHECK_THROWS_WITH_AS(s.save((dir / "missing" / "x.mesh").string()), doctest::Contains("does not exist"), Error);
  CHECK_FALSE(fs::exists(dir / "missing"));
}

TEST_CASE("editor: Open, Restore and Quit ask first when the session has unsaved changes, not otherwise") {
  const auto dir = test::temp_dir("editor_unsaved_request");
  const std::string cube = (dir / "cube.mesh").string();
  write_mesh_data(cube, test::cube());
  EditorSession s;
  ViewState v;
  PanelState p;
  // Nothing unsaved: done at once.
  request(s, v, p, {PanelState::Action::Open, test::asset_file("demo.mesh"), {}});
  CHECK(s.mesh_path() == test::asset_file("demo.mesh"));
  CHECK_FALSE(p.ask_unsaved);
  s.step();
  s.wait();
  REQUIRE(s.dirty());
  // Unsaved: the action waits for the dialog; the session is unchanged.
  for (const PanelState::Pending& a : {PanelState::Pending{PanelState::Action::Open, cube, {}},
                                       PanelState::Pending{PanelState::Action::Restore, (dir / "x.anisurf").string(), {}},
                                       PanelState::Pending{PanelState::Action::Quit, {}, {}}}) {
    p.ask_unsaved = false;
    request(s, v, p, a);
    CHECK(p.ask_unsaved);
    CHECK(p.pending.action == a.action);
    CHECK(s.mesh_path() == test::asset_file("demo.mesh"));
    CHECK(s.timeline().size() == 2);
    CHECK_FALSE(p.quit_confirmed);
  }
  // Saved: quitting does not ask.
  s.save((dir / "saved.mesh").string());
  p = {};
  request(s, v, p, {PanelState::Action::Quit, {}, {}});
  CHECK(p.quit_confirmed);
  CHECK_FALSE(p.ask_unsaved);
}

TEST_CASE("editor: Ctrl+Q quits a saved session at once and asks on unsaved changes (window under Xvfb)") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0 || std::system("command -v xdotool >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run or xdotool not installed");
    return;
  }
  const auto dir = test::temp_dir("editor_quit_window");
  const std::string cube = (dir / "cube.mesh").string();
  write_mesh_data(cube, test::cube());
  // "alive" once the process survived Ctrl+Q by 4 s; "exited" when it ended by itself.
  auto launch = [&](bool edit) {
    std::ostringstream cmd;
    cmd << "XDG_STATE_HOME='" << (dir / "state").string() << "' xvfb-run -a -s '-screen 0 1280x800x24' sh -c '\""
        << ANISURF_BINARY << "\" \"" << cube << "\" & pid=$!; "
        << "timeout 30 xdotool search --sync --onlyvisible --name \"anisurf editor\" >/dev/null; sleep 2; "
        << "xdotool mousemove 800 450" << (edit ? " key space; sleep 2; xdotool" : "") << " key ctrl+q; sleep 4; "
        << "if kill -0 $pid 2>/dev/null; then echo alive; kill $pid; else echo exited; fi; wait $pid' >'"
        << (dir / "stdout.txt").string() << "' 2>'" << (dir / "stderr.txt").string() << "'";
    std::system(cmd.str().c_str());
    return test::file_bytes(dir / "stdout.txt");
  };
  CHECK(launch(false).find("exited") != std::string::npos);
  CHECK(launch(true).find("alive") != std::string::npos);
}

TEST_CASE("editor metric panel: a typed value stays in the draft until committed (Enter, Tab, focus loss alike)") {
  EditorSession s;
  s.open(test::asset_file("demo.mesh"));
  SettingsDraft d;
  CHECK(d.follow(s.settings()));
  CHECK_FALSE(d.pending());
  d.edit.hmin = 0.001;  // typed into the field, which then loses focus
  // The frames before the commit: the session did not change, the draft stays.
  for (int frame = 0; frame < 3; ++frame) CHECK_FALSE(d.follow(s.settings()));
  CHECK(d.pending());
  CHECK(d.edit.hmin == 0.001);
  s.set_settings(d.edit);  // the commit
  CHECK(s.settings().hmin == 0.001);
  CHECK(d.follow(s.settings()));
  CHECK_FALSE(d.pending());
  // The session changed by other means (undo): the fields follow it.
  d.edit.iso = 0.5;
  REQUIRE(s.undo());
  CHECK(d.follow(s.settings()));
  CHECK(d.edit.hmin == 0);
  CHECK(d.edit.iso == s.settings().iso);
}

TEST_CASE("editor open: a loaded metric is used as given (no gradation, no bounds)") {
  EditorSession s;
  MetricSettings graded;
  graded.hgrad = 1.3;
  graded.hmin = 0.01;
  s.open(test::asset_file("demo.mesh"));
  s.set_settings(graded);
  s.open(test::asset_file("demo.mesh"), test::asset_file("demo.sol"));
  CHECK(s.settings().source == MetricSettings::Source::Sol);
  CHECK(s.settings().hgrad <= 1);
  CHECK(s.settings().hmin == 0);
  CHECK(std::isinf(s.settings().hmax));
  BuildReport report;
  SurfaceMesh with = load_mesh(test::asset_file("demo.mesh"), &report);
  attach_fields(with, read_sol(test::asset_file("demo.sol"), report.input_vertices), report);
  const MetricField file = metric_from_field(with, {}, report.vertex_origin);
  REQUIRE(file.size() == s.metric().size());
  for (std::size_t i = 0; i < file.size(); ++i) REQUIRE(file[i].m == s.metric()[i].m);
  // Another mesh opened without a metric: the previous file is not offered for it.
  {
    EditorSession o;
    o.open(test::asset_file("demo.mesh"), test::asset_file("demo.sol"));
    o.open(test::asset_file("demo.mesh"));
    CHECK(o.settings().source == MetricSettings::Source::Iso);
    CHECK(o.settings().sol_path.empty());
  }
  // Asked for, the gradation applies (and the file is read again).
  MetricSettings g = s.settings();
  g.hgrad = 1.1;
  s.set_settings(g);
  bool differs = false;
  for (std::size_t i = 0; i < file.size() && !differs; ++i) differs = file[i].m != s.metric()[i].m;
  CHECK(differs);
}

TEST_CASE("editor features: listed in the .mesh, kept as given, saved and read back with the session") {
  const auto dir = test::temp_dir("editor_features");
  // A file that lists its features: only those (the cube's other edges are
  // as sharp, a detection would tag all twelve).
  EditorSession s;
  s.open(write_cube_with_listed_features(dir));
  CHECK(s.features_from_file());
  CHECK(s.features().feature_edges == 4);
  CHECK(s.features().corners == 4);
  // A file without: detected.
  {
    const std::string plain = (dir / "cube.mesh").string();
    write_mesh_data(plain, test::cube());
    EditorSession p;
    p.open(plain);
    CHECK_FALSE(p.features_from_file());
    CHECK(p.features().feature_edges == 12);
    CHECK(p.features().corners == 8);
  }
  // The session: adapt, save the mesh and its metric, reopen both.
  MetricSettings m = s.settings();
  m.source = MetricSettings::Source::Iso;
  m.iso = 0.3;
  s.set_settings(m);
  s.run(3);
  s.wait();
  REQUIRE(s.adaptation_error().empty());
  const auto shown = s.display().snapshot;
  REQUIRE(shown->mesh.n_vertices() > 30);
  const std::string out = (dir / "cube_listed.adapted.mesh").string(), out_sol = (dir / "cube_listed.adapted.sol").string();
  s.save(out, out_sol);
  const MeshData written = read_mesh_data(out);
  CHECK(!written.ridges.empty());
  CHECK(written.corners.size() == 4);
  EditorSession r;
  r.open(out, out_sol);
  CHECK(r.features_from_file());
  const FeatureSets a = feature_sets(shown->mesh), b = feature_sets(r.input());
  CHECK(a.ridges.size() == written.ridges.size());
  CHECK(b.ridges == a.ridges);
  CHECK(b.corners == a.corners);
  CHECK(r.features().corners == 4);
  // The metric as saved (no gradation on top).
  CHECK(r.settings().hgrad <= 1);
  CHECK(r.predicted_vertices() == doctest::Approx(anisurf::predicted_vertices(shown->mesh, shown->metric)).epsilon(1e-6));
}

// The acceptance test of the work protection: an earlier session's autosave
// is left as it was by a later launch (on another mesh, for 15 s, with an
// edit when xdotool can type one) and is offered by it.
TEST_CASE("editor: a launch never changes an earlier session's autosave, and offers it (window under Xvfb)") {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: xvfb-run not installed (apt-get install xvfb xauth)");
    return;
  }
  const auto dir = test::temp_dir("editor_autosave_launch");
  const fs::path state = dir / "state", autosaves = state / "anisurf";
  fs::create_directories(autosaves);
  // The earlier session: an autosave as a launch writes it.
  std::string earlier;
  {
    Autosave a(autosaves.string(), std::time(nullptr) - 3600, 4242);
    REQUIRE(a.write({"open " + test::asset_file("demo.mesh"), "metric iso 0.2", "step"}));
    earlier = a.path();
  }
  const auto earlier_time = fs::last_write_time(earlier);
  const std::string earlier_bytes = test::file_bytes(earlier);
  // The later launch, on another mesh (the cube), for about 15 s; with
  // xdotool, a Space key press once its window shows (one adaptation pass:
  // an edit its own autosave keeps).
  const std::string cube = (dir / "cube.mesh").string();
  write_mesh_data(cube, test::cube());
  const bool typing = std::system("command -v xdotool >/dev/null 2>&1") == 0;
  std::ostringstream cmd;
  cmd << "XDG_STATE_HOME='" << state.string() << "' xvfb-run -a -s '-screen 0 1280x800x24' sh -c '\"" << ANISURF_BINARY
      << "\" \"" << cube << "\" & pid=$!; "
      << (typing ? "timeout 30 xdotool search --sync --onlyvisible --name \"anisurf editor\" >/dev/null; sleep 2; "
                   "xdotool mousemove 800 450 key space; sleep 12; "
                 : "sleep 15; ")
      << "kill $pid; wait $pid' >'"
      << (dir / "stdout.txt").string() << "' 2>'" << (dir / "stderr.txt").string() << "'";
  std::system(cmd.str().c_str());
  const std::string err = test::file_bytes(dir / "stderr.txt");
  INFO(err);
  CHECK(err.find("offering the autosave of an earlier session: " + earlier) != std::string::npos);
  CHECK(test::file_bytes(earlier) == earlier_bytes);
  CHECK(fs::last_write_time(earlier) == earlier_time);
  if (typing) {
    // The launch's own autosave: another file, on the cube, with the step.
    const auto listed = list_autosaves(autosaves.string(), earlier);
    REQUIRE(listed.size() == 1);
    CHECK(fs::path(listed[0].path).filename().string().rfind("cube-", 0) == 0);
    CHECK(test::file_bytes(listed[0].path).find("\nstep\n") != std::string::npos);
  } else {
    MESSAGE("xdotool not installed: the launch made no edit (its own autosave not checked)");
  }
}

#endif
