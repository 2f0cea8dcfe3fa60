// `anisurf adapt`: outputs (mesh, metric .sol, JSON report), Mmg's spellings,
// bad command lines, and the result measured by the independent evaluator.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sys/wait.h>

#include "io/mesh_io.h"
#include "metric/metric.h"
#include "test_util.h"

using namespace anisurf;

namespace {

using test::capture;

std::string adapt(const std::string& args, int* status) {
  return capture(std::string(ANISURF_BINARY) + " adapt " + args + " 2>/dev/null", status);
}

}  // namespace

TEST_CASE("anisurf adapt hemi: mesh, metric and report written, metric SPD, evaluator agrees on the band") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("adapt_hemi");
  const std::string out = (dir / "out.mesh").string(), report = (dir / "report.json").string();
  int status = -1;
  // --hausd 0: the iso metric alone (no geometry protection), which the evaluator is given
  const std::string text =
      adapt("'" + mesh + "' --sol '" + sol + "' --hausd 0 --lmin 0.72 -o '" + out + "' --report '" + report + "'", &status);
  REQUIRE(status == 0);
  CHECK(text.find("in band") != std::string::npos);
  const SurfaceMesh m = load_mesh(out);
  CHECK(m.validate().ok());
  CHECK(m.n_vertices() > 500);
  const auto fields = read_sol((dir / "out.sol").string(), m.n_vertices());
  REQUIRE(!fields.empty());
  REQUIRE(fields[0].info.kind == FieldKind::Tensor);
  for (int v = 0; v < m.n_vertices(); ++v) {
    std::array<double, 6> t{};
    for (int k = 0; k < 6; ++k) t[k] = fields[0].values[6 * v + k];
    CHECK(is_spd(SymTensor3(t)));
  }
  std::ifstream in(report);
  const nlohmann::json j = nlohmann::json::parse(in);
  REQUIRE(j["passes"].size() > 3);
  for (const auto& p : j["passes"]) CHECK(p["histogram"].size() == 9);
  CHECK(j["final"]["in_band_pct"].get<double>() > 90.0);
  CHECK(j["final"]["q_min"].get<double>() > 0.3);

  ANISURF_REQUIRE_SHARED(eval, "bench/eval.py");
  if (std::system("python3 -c 'import json' >/dev/null 2>&1") != 0) return;
  const std::string e = capture("python3 '" + eval + "' '" + out + "' --metric iso:0.085 --json");
  REQUIRE(!e.empty());
  const nlohmann::json ej = nlohmann::json::parse(e);
  CHECK(ej["len_in_range_pct"].get<double>() > 90.0);
  CHECK(ej["len_in_range_pct"].get<double>() == doctest::Approx(j["final"]["in_band_pct"].get<double>()).epsilon(0.02));
}

TEST_CASE("anisurf adapt: Mmg spellings (-in -sol -out -hgrad -1 -hmax -ar -v)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/square3d.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/square3d.sol");
  const auto dir = test::temp_dir("adapt_mmg");
  const std::string out = (dir / "sq.mesh").string();
  int status = -1;
  adapt("-in '" + mesh + "' -sol '" + sol + "' -out '" + out + "' -hgrad -1 -hmax 0.5 -ar 30 -v 0", &status);
  REQUIRE(status == 0);
  const SurfaceMesh m = load_mesh(out);
  CHECK(m.validate().ok());
  // The unit square keeps its corners and its boundary.
  int corners = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v)
    if (m.has_tag(Vertex(v), kCorner)) ++corners;
  CHECK(corners == 4);
  const BBox b = m.bbox();
  CHECK(b.lo.x == doctest::Approx(0.0));
  CHECK(b.hi.x == doctest::Approx(1.0));
  CHECK(b.lo.y == doctest::Approx(0.0));
  CHECK(b.hi.y == doctest::Approx(1.0));
  CHECK(std::filesystem::exists(dir / "sq.sol"));
}

TEST_CASE("anisurf adapt: bad command lines exit with 2, bad inputs with 1, nothing written") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  const auto dir = test::temp_dir("adapt_bad");
  const std::string out = (dir / "o.mesh").string();
  int status = -1;
  adapt("'" + mesh + "' --size 0.1", &status);
  CHECK(status == 2);  // no output
  adapt("'" + mesh + "' -o '" + out + "'", &status);
  CHECK(status == 2);  // no metric
  adapt("'" + mesh + "' --size 0.1 --length cubic -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' --size 0.1 --lmin 2 --lmax 1 -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' --size 0.1 --strip-width -1 -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' --size 0.1 --repair-quality 1.5 -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' --size 0.1 --relocate-quality -0.5 -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' --sol '" + (dir / "missing.sol").string() + "' -o '" + out + "'", &status);
  CHECK(status == 1);
  adapt("'" + mesh + "' --size '0 - 1' -o '" + out + "'", &status);
  CHECK(status == 1);  // a negative size: refused with the vertex named
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("anisurf adapt: --surface polyhedral --relax 1 --length log: vertices on the input triangles") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("adapt_options");
  const std::string out = (dir / "o.mesh").string();
  int status = -1;
  adapt("'" + mesh + "' -sol '" + sol + "' --surface polyhedral --relax 1 --length log -v 0 -o '" + out + "'", &status);
  REQUIRE(status == 0);
  const SurfaceMesh m = load_mesh(out);
  CHECK(m.validate().ok());
  CHECK(m.n_vertices() > 500);
  // hemi.mesh is a coarse polyhedron inscribed in the unit sphere: on its
  // triangles, vertices are inside the sphere, by at most its chordal error.
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    const double r = norm(m.position(Vertex(v)));
    CHECK(r <= 1 + 1e-9);
    CHECK(r >= 1 - 0.05);
  }
  adapt("'" + mesh + "' -sol '" + sol + "' --surface nurbs -o '" + out + "'", &status);
  CHECK(status == 2);
  adapt("'" + mesh + "' -sol '" + sol + "' --relax -1 -o '" + out + "'", &status);
  CHECK(status == 2);
}

TEST_CASE("anisurf adapt --geometry: the coarse hemisphere (T_0) adapted on the G1 surface of the fine sphere (T_G)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  ANISURF_REQUIRE_SHARED(sphere, "bench/inputs/sphere20k.mesh");
  const auto dir = test::temp_dir("adapt_geometry");
  const std::string out = (dir / "o.mesh").string();
  int status = -1;
  // --hausd 0: the given iso metric as it is (the geometry protection would
  // refine it to 3.6k vertices, and the rim, a curve of T_0 but not of T_G,
  // then drifts by 4e-3 below its plane where its vertices are smoothed).
  adapt("'" + mesh + "' -sol '" + sol + "' --geometry '" + sphere + "' --lmin 0.72 --hausd 0 -v 0 -o '" + out + "'",
        &status);
  REQUIRE(status == 0);
  const SurfaceMesh m = load_mesh(out);
  CHECK(m.validate().ok());
  CHECK(m.n_vertices() > 500);
  // hemi.mesh's own triangles are up to 1.4e-2 inside the sphere; every
  // vertex of the result is on the fine sphere's G1 surface.
  double worst = 0, lowest = 0;
  for (int v = 0; v < m.vertex_capacity(); ++v) {
    worst = std::max(worst, std::abs(norm(m.position(Vertex(v))) - 1));
    lowest = std::min(lowest, m.position(Vertex(v)).z);
  }
  CHECK(worst < 1e-5);
  // The rim stays in its plane up to the surface's accuracy there: it is
  // no curve of T_G (the whole sphere), so its new vertices are points of
  // the rim's chords put on the G1 surface of the sphere's triangles.
  CHECK(lowest > -1e-3);
}

namespace {

// Lines of `text` starting with `prefix` (after the leading spaces) ... counted.
int count_lines(const std::vector<std::string>& lines, const std::string& word) {
  int n = 0;
  for (const auto& l : lines) {
    const auto first = l.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    const auto space = l.find(' ', first);  // after the round number
    if (space != std::string::npos && l.compare(space + 1, word.size(), word) == 0) ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("anisurf adapt progress, stderr to a pipe: one line per round with its rate, never a '\\r', -v 0 and -v 2") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("adapt_progress_pipe");
  const std::string out = (dir / "out.mesh").string(), report = (dir / "report.json").string();
  // One thread: one region, whose every round has its line (remeshed in
  // regions, each region prints its final line).
  const std::string cmd = "ANISURF_PROGRESS_DELAY=0 " + std::string(ANISURF_BINARY) + " adapt '" + mesh + "' -sol '" +
                          sol + "' -o '" + out + "' --report '" + report + "' --threads 1";
  int status = -1;
  // stderr into the pipe, stdout (the summary table) away.
  const std::string err = capture(cmd + " 2>&1 >/dev/null", &status);
  REQUIRE(status == 0);
  CHECK(err.find('\r') == std::string::npos);  // not a terminal: no live line, even with no delay
  REQUIRE(!err.empty());
  CHECK(err.back() == '\n');
  std::ifstream in(report);
  const nlohmann::json j = nlohmann::json::parse(in);
  int rounds = 0;
  for (const auto& p : j["passes"]) rounds = std::max(rounds, p["round"].get<int>());
  const auto lines = test::render_terminal(err);
  REQUIRE(lines.size() >= 3);
  CHECK(lines.front().rfind("adapt: ", 0) == 0);
  CHECK(count_lines(lines, "round ") == rounds);
  CHECK(rounds >= 2);
  for (const auto& l : lines)
    if (l.find(" round ") != std::string::npos) {
      CAPTURE(l);
      CHECK(l.find(" split ") != std::string::npos);
      CHECK(l.find(" op/s") == l.size() - 5);  // the rate ends the line
    }
  CHECK(count_lines(lines, "final ") == 1);
  CHECK(lines[lines.size() - 2].find(" final ") != std::string::npos);
  CHECK(lines.back().empty());

  // -v 0: nothing on stderr; the summary table still on stdout.
  std::string quiet_out = capture(cmd + " -v 0 2>" + (dir / "quiet.err").string(), &status);
  REQUIRE(status == 0);
  CHECK(quiet_out.find("in band") != std::string::npos);
  CHECK(std::filesystem::file_size(dir / "quiet.err") == 0);

  // -v 2: one line per pass, each with its rate.
  const std::string passes = capture(cmd + " -v 2 2>&1 >/dev/null", &status);
  REQUIRE(status == 0);
  CHECK(passes.find('\r') == std::string::npos);
  int rated = 0;
  for (const auto& l : test::render_terminal(passes)) rated += l.find(" op/s") != std::string::npos;
  CHECK(rated == static_cast<int>(j["passes"].size()));
}

TEST_CASE("anisurf adapt progress on a terminal (script's pseudo-terminal): a live line rewritten with '\\r', erased at the end") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(sol, "bench/inputs/hemi_iso.sol");
  if (std::system("script -qec true /dev/null </dev/null >/dev/null 2>&1") != 0) {
    MESSAGE("skipped: no `script` (util-linux) to run under a pseudo-terminal");
    return;
  }
  const auto dir = test::temp_dir("adapt_progress_tty");
  const std::string out = (dir / "out.mesh").string();
  // Only stderr reaches the terminal; no delay (the hemisphere takes 0.1 s).
  // One thread: the serial loop's lines (on two, the hemisphere's 10k
  // triangles are two regions, whose lines name them).
  const std::string inner = std::string(ANISURF_BINARY) + " adapt '" + mesh + "' -sol '" + sol + "' -o '" + out +
                            "' --threads 1 >/dev/null";
  int status = -1;
  std::string tty = capture("ANISURF_PROGRESS_DELAY=0 COLUMNS=100 script -qec \"" + inner + "\" /dev/null </dev/null", &status);
  REQUIRE(status == 0);
  // The terminal writes '\n' as "\r\n"; what is left are the live line's '\r'.
  std::string text;
  for (std::size_t i = 0; i < tty.size(); ++i)
    if (!(tty[i] == '\r' && i + 1 < tty.size() && tty[i + 1] == '\n')) text += tty[i];
  CAPTURE(text);
  CHECK(text.find("\rinitial swap ") != std::string::npos);
  CHECK(text.find("\rround 1 split    [") != std::string::npos);
  CHECK(text.find("\rround 2 smooth   [") != std::string::npos);
  int updates = 0;
  for (std::size_t i = 0; i + 5 < text.size(); ++i) updates += text.compare(i, 6, "\rround") == 0;
  CHECK(updates >= 8);  // every pass of the rounds
  REQUIRE(!text.empty());
  CHECK(text.back() == '\n');
  // On screen at the end: the setup line, the round lines, the final line; the live line erased.
  const auto lines = test::render_terminal(text);
  REQUIRE(lines.size() >= 4);
  CHECK(lines.front().rfind("adapt: ", 0) == 0);
  CHECK(lines[lines.size() - 2].find(" final ") != std::string::npos);
  CHECK(lines.back().empty());
  for (const auto& l : lines) {
    CAPTURE(l);
    CHECK(l.rfind("round ", 0) == std::string::npos);
    if (l.rfind("adapt: ", 0) == 0) continue;  // the setup line holds the file paths
    CHECK(l.size() < 200);  // no leftover of a live line
  }
  CHECK(count_lines(lines, "round ") >= 2);
}

namespace {

// A scalar .sol of f at the vertices of the Medit mesh `mesh_path` (file order).
void write_field_sol(const std::string& mesh_path, const std::string& sol_path, double (*f)(const Vec3&)) {
  const MeshData d = read_mesh_data(mesh_path);
  FieldData fd;
  fd.info = FieldInfo{"f", FieldKind::Scalar, 1};
  for (const Vec3& p : d.vertices) fd.values.push_back(f(p));
  write_sol(sol_path, {fd}, static_cast<int>(d.vertices.size()), 3);
}

// Largest |value - f(vertex)| over the output mesh and its OUT.fields.sol.
double worst_field_error(const std::string& mesh_path, const std::string& fields_path, double (*f)(const Vec3&)) {
  const MeshData d = read_mesh_data(mesh_path);
  const std::vector<FieldData> fields = read_sol(fields_path, static_cast<int>(d.vertices.size()));
  REQUIRE(fields.size() == 1);
  REQUIRE(fields[0].values.size() == d.vertices.size());
  double worst = 0;
  for (std::size_t i = 0; i < d.vertices.size(); ++i) worst = std::max(worst, std::abs(fields[0].values[i] - f(d.vertices[i])));
  return worst;
}

}  // namespace

TEST_CASE("anisurf adapt --interpolate: a solution on the input carried onto the output (OUT.fields.sol)") {
  ANISURF_REQUIRE_SHARED(square, "bench/inputs/square3d.mesh");
  ANISURF_REQUIRE_SHARED(square_sol, "bench/inputs/square3d.sol");
  ANISURF_REQUIRE_SHARED(hemi, "bench/inputs/hemi.mesh");
  ANISURF_REQUIRE_SHARED(hemi_sol, "bench/inputs/hemi_iso.sol");
  const auto dir = test::temp_dir("adapt_interpolate");
  auto linear = [](const Vec3& p) { return 3 * p.x - p.y + 2 * p.z + 0.5; };
  // Flat square: the output lies in T_0's plane, a linear field is carried exactly.
  {
    const std::string f = (dir / "square_f.sol").string(), out = (dir / "square.mesh").string();
    write_field_sol(square, f, linear);
    int status = -1;
    const std::string text = adapt("'" + square + "' -sol '" + square_sol + "' --interpolate '" + f + "' -o '" + out + "'", &status);
    REQUIRE(status == 0);
    CHECK(text.find("square.fields.sol") != std::string::npos);  // named in the summary
    CHECK(worst_field_error(out, (dir / "square.fields.sol").string(), linear) < 1e-12);
    // The metric file holds the metric alone (Mmg reads it).
    CHECK(read_sol((dir / "square.sol").string(), static_cast<int>(read_mesh_data(out).vertices.size())).size() == 1);
  }
  // Coarse hemisphere: new vertices lie on the G1 surface (the unit sphere to
  // 2e-4), up to 0.045 off T_0's 66-vertex triangles, where the field is
  // read (at the closest point): off by at most |grad f| = sqrt 14 times that.
  {
    const std::string f = (dir / "hemi_f.sol").string(), out = (dir / "hemi.mesh").string();
    write_field_sol(hemi, f, linear);
    int status = -1;
    adapt("'" + hemi + "' -sol '" + hemi_sol + "' --interpolate '" + f + "' -o '" + out + "'", &status);
    REQUIRE(status == 0);
    const double err = worst_field_error(out, (dir / "hemi.fields.sol").string(), linear);
    MESSAGE("hemi: worst |f - f(x)| " << err);
    CHECK(err < std::sqrt(14.0) * 0.05);
  }
  // A field file for another mesh is refused, nothing written.
  {
    const std::string f = (dir / "square_f.sol").string(), out = (dir / "bad.mesh").string();
    int status = -1;
    adapt("'" + hemi + "' -sol '" + hemi_sol + "' --interpolate '" + f + "' -o '" + out + "'", &status);
    CHECK(status == 1);
    CHECK(!std::filesystem::exists(out));
  }
}

TEST_CASE("anisurf adapt --threads: regions in the report, the same output twice, bad counts refused") {
  const std::string mesh = test::asset_file("demo.mesh");
  const auto dir = test::temp_dir("adapt_threads");
  int status = -1;
  auto run = [&](const std::string& name, int threads) {
    const std::string out = (dir / (name + ".mesh")).string(), report = (dir / (name + ".json")).string();
    adapt("'" + mesh + "' --size 0.012 --threads " + std::to_string(threads) + " --report '" + report + "' -o '" + out +
              "'",
          &status);
    REQUIRE(status == 0);
    std::ifstream f(report);
    return std::make_pair(test::file_bytes(out), nlohmann::json::parse(f));
  };
  const auto [one, one_report] = run("one", 1);
  const auto [two, two_report] = run("two", 2);
  const auto [again, again_report] = run("again", 2);
  CHECK(two == again);
  std::set<int> regions;
  for (const auto& p : two_report["passes"]) regions.insert(p["region"].get<int>());
  CHECK(regions.size() >= 3);  // two regions or more, then the band
  CHECK(*regions.begin() == 0);
  CHECK(*regions.rbegin() == static_cast<int>(regions.size()) - 1);
  for (const auto& p : one_report["passes"]) CHECK(p["region"].get<int>() == -1);
  CHECK(two_report["final"]["in_band_pct"].get<double>() >= one_report["final"]["in_band_pct"].get<double>() - 1.0);
  CHECK(two_report["inverted"].get<int>() == 0);
  const SurfaceMesh out = load_mesh((dir / "two.mesh").string());
  CHECK(out.validate().ok());
  int open = 0;
  for (Corner c : out.edges()) open += out.is_boundary_edge(c);
  CHECK(open == 0);
  for (const char* bad : {"-1", "1.5", "x"}) {
    adapt("'" + mesh + "' --size 0.1 --threads " + std::string(bad) + " -o '" + (dir / "bad.mesh").string() + "'",
          &status);
    CHECK(status == 2);
  }
  CHECK(!std::filesystem::exists(dir / "bad.mesh"));
}

namespace {

// sphere20k adapted to size 0.02 on 2 threads with `option`: its JSON
// report, the output checked valid.
nlohmann::json adapt_sphere20k_report(const std::string& mesh, const std::filesystem::path& dir, const std::string& name,
                                      const std::string& option) {
  const std::string out = (dir / (name + ".mesh")).string(), report = (dir / (name + ".json")).string();
  int status = -1;
  adapt("'" + mesh + "' --size 0.02 --threads 2 " + option + " --report '" + report + "' -o '" + out + "'", &status);
  REQUIRE(status == 0);
  CHECK(load_mesh(out).validate().ok());
  std::ifstream f(report);
  return nlohmann::json::parse(f);
}

}  // namespace

TEST_CASE("anisurf adapt --repair-quality: the final passes' repairs, on by default, off with 0") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  const auto dir = test::temp_dir("adapt_repair");
  auto run = [&](const std::string& name, const std::string& option) {
    const nlohmann::json j = adapt_sphere20k_report(mesh, dir, name, option);
    int repairs = 0;
    for (const auto& p : j["passes"])
      if (p["pass"] == "final") repairs += p["collapses"].get<int>();
    return std::make_pair(repairs, j["final"]["q_min"].get<double>());
  };
  // The repair alone (the relocations after it off in both runs).
  const auto [repairs, q_min] = run("default", "--relocate-quality 0");
  const auto [none, q_min_off] = run("off", "--repair-quality 0 --relocate-quality 0");
  MESSAGE("final-pass repairs " << repairs << ", q min " << q_min_off << " -> " << q_min);
  CHECK(repairs > 0);
  CHECK(none == 0);
  CHECK(q_min >= q_min_off);
}

TEST_CASE("anisurf adapt --relocate-quality: the worst triangles' vertices relocated by default, not with 0") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/sphere20k.mesh");
  const auto dir = test::temp_dir("adapt_relocate");
  auto run = [&](const std::string& name, const std::string& option) {
    const nlohmann::json j = adapt_sphere20k_report(mesh, dir, name, option);
    return std::make_pair(j["final"]["q_min"].get<double>(), j["final"]["q_mean"].get<double>());
  };
  const auto [q_min, q_mean] = run("default", "");
  const auto [q_min_off, q_mean_off] = run("off", "--relocate-quality 0");
  MESSAGE("q min " << q_min_off << " -> " << q_min << ", mean " << q_mean_off << " -> " << q_mean);
  CHECK(q_min > q_min_off);
  CHECK(q_mean >= q_mean_off - 1e-5);
}
