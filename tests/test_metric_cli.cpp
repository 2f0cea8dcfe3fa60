// `anisurf quality` and `anisurf metric` against closed forms and against the
// independent evaluator ../shared/bench/eval.py.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sys/wait.h>

#include "io/mesh_io.h"
#include "metric/mesh_quality.h"
#include "metric/quality.h"
#include "test_util.h"

using namespace anisurf;

namespace {

using test::capture;

bool have_python() { return std::system("python3 -c 'import json' >/dev/null 2>&1") == 0; }

nlohmann::json quality_json(const std::string& mesh, const std::string& sol, const std::string& extra = "") {
  const std::string out = capture(std::string(ANISURF_BINARY) + " quality '" + mesh + "' --sol '" + sol + "' --json " + extra);
  REQUIRE_MESSAGE(!out.empty(), "anisurf quality printed nothing");
  return nlohmann::json::parse(out);
}

nlohmann::json eval_json(const std::string& eval, const std::string& mesh, const std::string& sol) {
  const std::string out = capture("python3 '" + eval + "' '" + mesh + "' --metric sol --sol '" + sol + "' --json");
  REQUIRE_MESSAGE(!out.empty(), "eval.py printed nothing");
  return nlohmann::json::parse(out);
}

}  // namespace

TEST_CASE("mesh quality: closed forms on the unit square") {
  SurfaceMesh m;
  Vertex a = m.add_vertex(Vec3(0, 0, 0)), b = m.add_vertex(Vec3(1, 0, 0)), c = m.add_vertex(Vec3(1, 1, 0)),
         d = m.add_vertex(Vec3(0, 1, 0));
  m.add_triangle(a, b, c);
  m.add_triangle(a, c, d);
  // h = 1.01: lengths 1/1.01 (x4) and sqrt2/1.01 (diagonal): all in the band.
  MetricField M(4, isotropic_metric(1.01));
  MeshQuality q = measure_mesh_quality(m, M);
  CHECK(q.edges == 5);
  CHECK(q.in_band_share == 1.0);
  CHECK(q.length_max == doctest::Approx(std::sqrt(2.0) / 1.01));
  CHECK(q.histogram[4] == 4);  // [0.9, 1.3)
  CHECK(q.histogram[5] == 1);  // [1.3, sqrt2)
  const double p = 1 + std::sqrt(0.5);
  const double right = 27 * (p - 1) * (p - 1) * (p - std::sqrt(2.0)) / (p * p * p);
  CHECK(q.q_min == doctest::Approx(right));
  CHECK(q.q_mean == doctest::Approx(right));
  CHECK(q.mean_ratio_mean == doctest::Approx(std::sqrt(3.0) / 2));
  CHECK(q.complexity == doctest::Approx(1.0 / (1.01 * 1.01)));
  M.assign(4, isotropic_metric(1.0));
  // h = 0.5 on the right side, 1 on the left: eq. 7 gives 1 * 0.5 ln 2 / 0.5 for the bottom edge.
  M[1] = M[2] = isotropic_metric(0.5);
  MeshQualityOptions o;
  o.length = LengthFormula::LinearSize;
  q = measure_mesh_quality(m, M, o);
  CHECK(q.length_min == doctest::Approx(1.0));                // the left edge (h = 1)
  CHECK(q.length_max == doctest::Approx(2.0));                // the right edge (h = 0.5)
  CHECK(q.length_mean == doctest::Approx((1.0 + 2.0 + 2 * std::log(2.0) / 0.5 + std::sqrt(2.0) * std::log(2.0) / 0.5) / 5));
}

TEST_CASE("anisurf quality agrees with eval.py on the share of edges in the band (within 0.5 points)") {
  ANISURF_REQUIRE_SHARED(eval, "bench/eval.py");
  if (!have_python()) {
    MESSAGE("skipped: python3 not available");
    return;
  }
  const std::string in = anisurf::test::shared_file("bench/inputs");
  struct Case {
    std::string mesh, sol;
  };
  std::vector<Case> cases = {{in + "/sphere20k.mesh", in + "/sphere20k_iso.sol"},
                             {in + "/sphere20k.mesh", in + "/sphere20k_band.sol"},
                             {in + "/hemi.mesh", in + "/hemi_iso.sol"},
                             {in + "/square3d.mesh", in + "/square3d.sol"}};
  // A smooth anisotropic tensor field on the sphere with most edges near the
  // band (the bench inputs are far from unit meshes): sizes around the mesh's
  // own edge length, varying with position, axes rotating with x.
  {
    BuildReport r;
    const SurfaceMesh sphere = load_mesh(in + "/sphere20k.mesh", &r);
    FieldData f;
    f.info = FieldInfo{"metric", FieldKind::Tensor, 6};
    for (int i = 0; i < r.input_vertices; ++i) {
      const Vec3 x = sphere.position(Vertex(r.vertex_map[i]));
      const double h1 = 0.035 * (1.3 + 0.5 * x.z), h2 = 0.045 * (1.2 - 0.4 * x.y), h3 = 0.04;
      const double a = 1.5 * x.x;
      const SymTensor3 M = metric_from_sizes({h1, h2, h3}, {Vec3(std::cos(a), std::sin(a), 0),
                                                            Vec3(-std::sin(a), std::cos(a), 0), Vec3(0, 0, 1)});
      f.values.insert(f.values.end(), M.m.begin(), M.m.end());
    }
    const auto dir = anisurf::test::temp_dir("metric_quality");
    write_sol((dir / "smooth.sol").string(), {f}, r.input_vertices);
    cases.push_back({in + "/sphere20k.mesh", (dir / "smooth.sol").string()});
  }
  // The band metric after gradation by `anisurf metric` (smooth transitions).
  {
    const auto dir = anisurf::test::temp_dir("metric_quality_graded");
    const std::string graded = (dir / "graded.sol").string();
    int rc = -1;
    capture(std::string(ANISURF_BINARY) + " metric '" + in + "/sphere20k.mesh' --sol '" + in +
                "/sphere20k_band.sol' --hgrad 1.3 -o '" + graded + "'",
            &rc);
    REQUIRE(rc == 0);
    cases.push_back({in + "/sphere20k.mesh", graded});
  }
  for (const Case& c : cases) {
    CAPTURE(c.sol);
    const nlohmann::json ours = quality_json(c.mesh, c.sol), ref = eval_json(eval, c.mesh, c.sol);
    MESSAGE(c.sol << ": in band " << ours["len_in_range_pct"].get<double>() << " % ("
                  << ours["length_formula"].get<std::string>() << ") vs eval.py "
                  << ref["len_in_range_pct"].get<double>() << " %; q_mean " << ours["q_mean"].get<double>() << " vs "
                  << ref["q_mean"].get<double>());
    CHECK(ours["ne"].get<int>() == ref["ne"].get<int>());
    CHECK(std::fabs(ours["len_in_range_pct"].get<double>() - ref["len_in_range_pct"].get<double>()) <= 0.5);
    CHECK(ours["len_mean"].get<double>() == doctest::Approx(ref["len_mean"].get<double>()).epsilon(0.01));
    CHECK(ours["q_mean"].get<double>() == doctest::Approx(ref["q_mean"].get<double>()).epsilon(0.01));
  }
}

namespace {

std::vector<SymTensor3> read_metric_sol(const std::string& path, int n) {
  const auto fields = read_sol(path, n);
  REQUIRE(fields.size() == 1);
  REQUIRE(fields[0].info.ncomp == 6);
  std::vector<SymTensor3> out;
  for (int i = 0; i < n; ++i) {
    SymTensor3 M;
    for (int k = 0; k < 6; ++k) M.m[k] = fields[0].values[6 * i + k];
    out.push_back(M);
  }
  return out;
}

}  // namespace

TEST_CASE("anisurf metric square3d.mesh --hessian-of 100*x^2 --error 0.01: M = diag(2/9 200/0.01, hmax^-2, hmax^-2)") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/square3d.mesh");
  const auto dir = anisurf::test::temp_dir("metric_square");
  for (const char* hmax : {"1", ""}) {
    const std::string out = (dir / "m.sol").string();
    int rc = -1;
    const std::string cmd = std::string(ANISURF_BINARY) + " metric '" + mesh +
                            "' --hessian-of '100*x^2' --error 0.01 " + (*hmax ? std::string("--hmax ") + hmax : "") +
                            " -o '" + out + "'";
    const std::string log = capture(cmd + " 2>&1", &rc);
    CAPTURE(log);
    REQUIRE(rc == 0);
    // hmax defaults to the bounding-box diagonal, sqrt 2 for the unit square.
    const double h2 = *hmax ? 1.0 : 0.5;
    const auto M = read_metric_sol(out, 121);
    for (const SymTensor3& X : M) {
      CHECK(X.xx() == doctest::Approx(2.0 / 9.0 * 200.0 / 0.01).epsilon(1e-9));
      CHECK(X.yy() == doctest::Approx(h2).epsilon(1e-9));
      CHECK(X.zz() == doctest::Approx(h2).epsilon(1e-9));
      CHECK(std::fabs(X.xy()) < 1e-6);
      CHECK(std::fabs(X.xz()) < 1e-9);
      CHECK(std::fabs(X.yz()) < 1e-9);
    }
  }
}

TEST_CASE("anisurf metric: errors name the expression, its position or the vertex, bad usage exits with 2") {
  ANISURF_REQUIRE_SHARED(mesh, "bench/inputs/square3d.mesh");
  const auto dir = anisurf::test::temp_dir("metric_errors");
  const std::string out = (dir / "m.sol").string();
  const std::string base = std::string(ANISURF_BINARY) + " metric '" + mesh + "' ";
  int rc = -1;
  std::string log = capture(base + "--hessian-of '100*x^^2' --error 0.01 -o '" + out + "' 2>&1", &rc);
  CHECK(rc == 1);
  CHECK(log.find("'100*x^^2'") != std::string::npos);
  CHECK(log.find("position 6") != std::string::npos);
  log = capture(base + "--size '1/x' -o '" + out + "' 2>&1", &rc);
  CHECK(rc == 1);
  CHECK(log.find("division by zero") != std::string::npos);
  CHECK(log.find("vertex 1 (1-based) at (x, y, z) = (0, 0, 0)") != std::string::npos);
  log = capture(base + "--size 0.1 --curvature --hausd 0.01 -o '" + out + "' 2>&1", &rc);
  CHECK(rc == 2);
  CHECK(log.find("exactly one source") != std::string::npos);
  log = capture(base + "--hessian-of 'x^2' -o '" + out + "' 2>&1", &rc);
  CHECK(rc == 2);
  // A size field written, read back: h = 0.1 + x, clamped to hmax = 0.5.
  log = capture(base + "--size '0.1 + x' --hmax 0.5 -o '" + out + "' 2>&1", &rc);
  REQUIRE(rc == 0);
  BuildReport r;
  const SurfaceMesh sq = load_mesh(mesh, &r);
  const auto M = read_metric_sol(out, r.input_vertices);
  for (int i = 0; i < r.input_vertices; ++i) {
    const double h = std::min(0.5, 0.1 + sq.position(Vertex(r.vertex_map[i])).x);
    CHECK(M[i].xx() == doctest::Approx(1 / (h * h)).epsilon(1e-12));
  }
  // --hgrad -1 turns the gradation off (as in `anisurf adapt` and Mmg): the
  // same field as without it, where a gradation of 1.05 changes it; a ratio
  // below 1 is refused.
  const std::string off = out + ".off.sol", graded = out + ".graded.sol";
  log = capture(base + "--size '0.1 + x' --hmax 0.5 --hgrad -1 -o '" + off + "' 2>&1", &rc);
  REQUIRE(rc == 0);
  log = capture(base + "--size '0.1 + x' --hmax 0.5 --hgrad 1.05 -o '" + graded + "' 2>&1", &rc);
  REQUIRE(rc == 0);
  const auto M_off = read_metric_sol(off, r.input_vertices), M_graded = read_metric_sol(graded, r.input_vertices);
  int changed = 0;
  for (int i = 0; i < r.input_vertices; ++i) {
    CHECK(M_off[i].m == M[i].m);
    changed += M_graded[i].m != M[i].m;
  }
  CHECK(changed > 0);
  log = capture(base + "--size 0.1 --hgrad 0.5 -o '" + out + "' 2>&1", &rc);
  CHECK(rc == 2);
  CHECK(log.find("--hgrad expects a ratio > 1, or -1 (off)") != std::string::npos);
}
