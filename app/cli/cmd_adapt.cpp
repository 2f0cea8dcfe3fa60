// `anisurf adapt`: the remesher of the report's section 6 on a surface mesh
// and a metric (Mmg's mmgs spellings accepted).
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <sys/ioctl.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/metric_options.h"
#include "cli/progress.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/features.h"
#include "io/mesh_io.h"
#include "metric/hessian.h"
#include "metric/metric_field.h"
#include "metric/surface_metric.h"
#include "remesh/remesher.h"

namespace anisurf::cli {

namespace {

const char* kAdaptHelp =
    "usage: anisurf adapt IN.mesh METRIC [options] -o OUT.mesh\n"
    "\n"
    "Adapts the surface mesh IN to a metric (Castro-Diaz & Hecht 1995, sections 5-6):\n"
    "splits of edges longer than lmax, collapses of edges shorter than lmin, swaps on\n"
    "the quality of eq. 17, smoothing (eq. 19), the final optimisation. New and moved\n"
    "vertices are projected onto the input surface (T_G) and take their metric from\n"
    "the input mesh (T_0). Writes OUT.mesh and its metric OUT.sol (tensors).\n"
    "\n"
    "METRIC (one source, as in `anisurf metric`):\n"
    "  --sol S | -sol S     metric tensors or sizes on the vertices of IN\n"
    "  --size EXPR          isotropic size h(x,y,z)\n"
    "  --tensor EXPR        'm11, m12, m22, m13, m23, m33'\n"
    "  --hessian-of EXPR    with --error EPS | --complexity C | --vertices N [--norm P]\n"
    "  --curvature          geometric metric from --hausd alone\n"
    "  --hmin A --hmax B    size bounds (also -hmin -hmax); --max-aniso K\n"
    "options:\n"
    "  --hausd D            chordal deviation: the metric is intersected with the\n"
    "                       curvature metric of D (also -hausd)\n"
    "  --hgrad R            size gradation ratio (default 1.3, Mmg's); -1 or 0: off\n"
    "  --ar DEG             ridge detection angle (default 45); --nr: no detection\n"
    "                       (also -ar, -nr); ridges and boundaries stay curves, corners stay\n"
    "  --lmin L --lmax L    edges shorter than lmin are collapsed, longer than lmax split\n"
    "                       (default 0.72 and 1.4: the edges end in [1/sqrt2, sqrt2],\n"
    "                       the band Mmg and bench/eval.py measure; the report's values\n"
    "                       are 0.6 and 1.4: --lmin 0.6)\n"
    "  --length F           linear (eq. 6, default) or log (eq. 7) edge lengths\n"
    "  --interpolation I    how T_0's metric is read between its vertices: size (the\n"
    "                       size M^-1/2 linear, default), linear (the coefficients,\n"
    "                       section 2.2), inverse (Remark 2) or log (log-Euclidean)\n"
    "  --surface S          g1: the G1 Bezier surface of section 3 at the parameters of\n"
    "                       the projection onto the input triangles (default);\n"
    "                       g1-closest: its closest point (slower); polyhedral\n"
    "  --geometry G         T_G: another mesh of the surface to project onto (e.g. a\n"
    "                       finer one); IN stays T_0, the metric's support\n"
    "  --iterations N       at most N rounds of split/collapse/swap/smooth (default 30)\n"
    "  --relax N            Remark 6: adapt first to N relaxed metrics between the\n"
    "                       input mesh's sizes and the target (default 0: off)\n"
    "  --report FILE        per-pass report (JSON)\n"
    "  --interpolate F.sol  a solution on IN's vertices (any fields), interpolated onto\n"
    "                       the output from T_0 (section 6); written to OUT.fields.sol\n"
    "  -v N                 verbosity on stderr: 0 quiet, 1 per round (default), 2 per\n"
    "                       pass; at 1 on a terminal, a live line (round, pass, counts,\n"
    "                       vertices against the metric's prediction, op/s) after each pass\n"
    "                       once the run has lasted ANISURF_PROGRESS_DELAY s (default 0.5)\n"
    "  -o OUT | -out OUT    output mesh (required); the metric goes to OUT.sol\n"
    "\n"
    "examples:\n"
    "  anisurf adapt sphere.mesh -sol sphere_iso.sol -o out.mesh\n"
    "  mmgs-style: anisurf adapt -in sphere.mesh -sol band.sol -hgrad -1 -out out.mesh\n";

// Width of the terminal on stderr (COLUMNS, else 80, when unknown).
int terminal_columns() {
  winsize ws{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  if (const char* c = std::getenv("COLUMNS"); c && std::atoi(c) > 0) return std::atoi(c);
  return 80;
}

std::string sol_path_for(const std::string& mesh_path) {
  std::filesystem::path p(mesh_path);
  p.replace_extension(".sol");
  return p.string();
}

// OUT.mesh -> OUT.fields.sol: the fields of --interpolate on the output.
std::string fields_path_for(const std::string& mesh_path) {
  std::filesystem::path p(mesh_path);
  p.replace_extension(".fields.sol");
  return p.string();
}

// Field names of --interpolate's fields on T_0 (apart from -sol's).
constexpr const char* kInterpolatedPrefix = "interpolate:";

nlohmann::json pass_json(const remesh::PassReport& r) {
  nlohmann::json j;
  j["pass"] = std::string(remesh::pass_name(r.kind));
  j["iteration"] = r.iteration;
  j["splits"] = r.splits;
  j["collapses"] = r.collapses;
  j["swaps"] = r.swaps;
  j["moves"] = r.moves;
  j["removed_vertices"] = r.removed_vertices;
  j["split_unprojected"] = r.split_unprojected;
  nlohmann::json rej = nlohmann::json::object();
  for (int i = 1; i < remesh::kRejectionCount; ++i)
    if (r.rejected[i]) rej[std::string(remesh::rejection_name(static_cast<remesh::Rejection>(i)))] = r.rejected[i];
  j["rejected"] = rej;
  j["vertices"] = r.vertices;
  j["triangles"] = r.triangles;
  j["edges"] = r.edges;
  j["histogram"] = r.histogram;
  j["in_band_pct"] = 100.0 * r.in_band_share;
  j["length_min"] = r.length_min;
  j["length_max"] = r.length_max;
  j["q_min"] = r.q_min;
  j["q_mean"] = r.q_mean;
  j["seconds"] = r.seconds;
  j["touched"] = r.touched.size();
  return j;
}

int run_adapt(const std::vector<std::string>& args) {
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  ArgParser p(args);
  std::string in = p.option("-in", "--input");
  std::string out = p.option("-o", "--output");
  if (out.empty()) out = p.option("-out");
  MetricSourceOptions mo = parse_metric_options(p);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double hausd = p.option_double("--hausd", nan);
  if (std::isnan(hausd)) hausd = p.option_double("-hausd", nan);
  double hgrad = p.option_double("--hgrad", nan);
  if (std::isnan(hgrad)) hgrad = p.option_double("-hgrad", 1.3);
  double ar = p.option_double("--ar", nan);
  if (std::isnan(ar)) ar = p.option_double("-ar", 45.0);
  const bool no_ridges = p.flag("--nr", "-nr");
  remesh::RemeshOptions ro;
  // The report's lmin 0.6 leaves edges in [0.6, 0.707): counted adapted by the
  // algorithm but outside the [1/sqrt2, sqrt2] band users measure.
  constexpr double kBandLmin = 0.72;
  ro.op.lmin = p.option_double("--lmin", kBandLmin);
  ro.op.lmax = p.option_double("--lmax", ro.op.lmax);
  ro.max_iterations = static_cast<int>(p.option_double("--iterations", ro.max_iterations));
  ro.relaxation_stages = static_cast<int>(p.option_double("--relax", 0));
  if (ro.relaxation_stages < 0) throw UsageError{"--relax expects a number of stages >= 0"};
  const std::string length = p.option("--length");
  const std::string interpolation_name = p.option("--interpolation");
  const std::string surface = p.option("--surface");
  const std::string geometry_path = p.option("--geometry");
  const std::string report_path = p.option("--report");
  const std::string interpolate_path = p.option("--interpolate");
  ro.record_touched = !report_path.empty();  // only the JSON report counts them
  std::string verb = p.option("-v", "--verbose");
  const int verbose = verb.empty() ? 1 : std::atoi(verb.c_str());
  // Every pass's state is printed (-v 2) or written (--report); else the round's last one.
  ro.measure_every_pass = verbose >= 2 || !report_path.empty();
  auto pos = p.positionals();
  if (in.empty() && !pos.empty()) {
    in = pos.front();
    pos.erase(pos.begin());
  }
  if (in.empty() || !pos.empty()) throw UsageError{"expected one input mesh"};
  if (out.empty()) throw UsageError{"-o OUT.mesh is required"};
  if (mo.source_count() > 1) throw UsageError{"give at most one metric source"};
  if (mo.source_count() == 0) {
    if (!(hausd > 0)) throw UsageError{"give a metric source (--sol, --size, ...) or --hausd D"};
    mo.curvature = true;
  }
  if (mo.curvature && !(hausd > 0)) throw UsageError{"--curvature needs --hausd D with D > 0"};
  if (!(ro.op.lmin > 0) || !(ro.op.lmax > ro.op.lmin)) throw UsageError{"need 0 < lmin < lmax"};
  if (!length.empty() && length != "linear" && length != "log")
    throw UsageError{"--length expects linear or log, got '" + length + "'"};
  // Across a sharp change of the metric between T_0's vertices (the band
  // cases), the size read linearly follows the intended field best
  // (sphere20k_band: q min 0.043 -> 0.252, qc mean 0.930 -> 0.944).
  MetricInterpolation interpolation = MetricInterpolation::LinearSize;
  if (interpolation_name == "linear")
    interpolation = MetricInterpolation::Linear;
  else if (interpolation_name == "inverse")
    interpolation = MetricInterpolation::Inverse;
  else if (interpolation_name == "log")
    interpolation = MetricInterpolation::LogEuclidean;
  else if (!interpolation_name.empty() && interpolation_name != "size")
    throw UsageError{"--interpolation expects size, linear, inverse or log, got '" + interpolation_name + "'"};
  if (!surface.empty() && surface != "g1" && surface != "g1-closest" && surface != "polyhedral")
    throw UsageError{"--surface expects g1, g1-closest or polyhedral, got '" + surface + "'"};
  const bool grade = hgrad > 1;
  if (!grade && hgrad != -1 && hgrad != 0 && hgrad != 1) throw UsageError{"--hgrad expects a ratio > 1, or -1 (off)"};

  // T_G = T_0: the input mesh with its features and its metric.
  BuildReport report;
  // -v 2: the time of each setup step.
  auto t_phase = Clock::now();
  const auto phase = [&](const char* what_phase) {
    const auto now = Clock::now();
    if (verbose >= 2) std::fprintf(stderr, "  setup: %-45s %.2f s\n", what_phase, std::chrono::duration<double>(now - t_phase).count());
    t_phase = now;
  };
  SurfaceMesh input = load_mesh(in, &report);
  phase("read the mesh");
  MetricField sol_metric;
  std::string metric_name;
  if (!mo.sol.empty()) {
    const auto fields = read_sol(mo.sol, report.input_vertices);
    attach_fields(input, fields, report);
    for (const auto& f : fields)
      if (metric_name.empty() && f.info.kind == FieldKind::Tensor) metric_name = f.info.name;
    for (const auto& f : fields)
      if (metric_name.empty() && f.info.kind == FieldKind::Scalar) metric_name = f.info.name;
    try {
      sol_metric = metric_from_field(input, {}, report.vertex_origin);
    } catch (const MetricError& e) {
      throw MetricError(mo.sol + ": " + e.what());
    }
  }
  // Section 6: a solution given on IN's vertices, interpolated onto the
  // adapted mesh from its location in T_0 (written to OUT.fields.sol).
  if (!interpolate_path.empty()) {
    auto fields = read_sol(interpolate_path, report.input_vertices);
    for (std::size_t k = 0; k < fields.size(); ++k) fields[k].info.name = kInterpolatedPrefix + std::to_string(k);
    attach_fields(input, fields, report);
  }
  FeatureOptions fo;
  fo.detect_ridges = !no_ridges;
  fo.ridge_angle_deg = ar;
  const FeatureReport fr = detect_features(input, fo);
  std::string what;
  MetricField metric = build_metric(input, report, std::move(sol_metric), mo, hausd, &what);
  if (hausd > 0 && !mo.curvature) {
    const MetricField geo = curvature_metric(input, hausd, mo.bounds);
    for (int v = 0; v < input.vertex_capacity(); ++v)
      if (!input.is_deleted(Vertex(v))) metric[v] = intersect(metric[v], geo[v]);
    what += ", intersected with hausd " + std::to_string(hausd);
  }
  if (grade) {
    GradationOptions g;
    g.ratio = hgrad;
    gradate_metric(input, metric, g);
  }
  check_metric_field(input, metric, report.vertex_origin);
  phase("metric (features, sources, gradation)");
  if (!metric_name.empty()) input.remove_field(metric_name);  // read into `metric`: T_0 need not keep it

  // T_G: the input itself, or another mesh of the same surface (--geometry).
  SurfaceMesh separate_geometry;
  const bool separate = !geometry_path.empty();
  if (separate) {
    separate_geometry = load_mesh(geometry_path);
    detect_features(separate_geometry, fo);
  }
  const SurfaceMesh& tg = separate ? separate_geometry : input;
  std::unique_ptr<remesh::GeometrySurface> geometry;
  if (surface == "polyhedral")
    geometry = std::make_unique<remesh::PolyhedralSurface>(tg);
  else
    geometry = std::make_unique<remesh::BezierGeometry>(
        tg, surface == "g1-closest" ? remesh::BezierGeometry::Mode::Closest : remesh::BezierGeometry::Mode::Parametric);
  phase("surface (frames, Bezier patches, locator)");
  remesh::ControlSpace control(input, std::move(metric), !separate, interpolation,
                               metric_name.empty() ? "metric" : metric_name);
  const LengthFormula formula = length == "log" ? LengthFormula::LinearSize : LengthFormula::LinearMetric;
  remesh::AdaptedMesh adapted(input, *geometry, control, formula, separate);
  phase("T_1 located on T_G and T_0");
  const double t_setup = std::chrono::duration<double>(Clock::now() - t_start).count();
  if (verbose >= 1)
    std::fprintf(stderr, "adapt: %s: %d vertices, %d triangles, %d feature edges, %d corners; metric %s; %s surface (%.2f s)\n",
                 in.c_str(), input.n_vertices(), input.n_triangles(), fr.feature_edges, fr.corners, what.c_str(),
                 geometry->name().c_str(), t_setup);

  remesh::Remesher remesher(adapted, ro);
  // Progress on stderr (cli/progress.h): one line per round (-v 1) or per pass
  // (-v 2); on a terminal, a live line below them rewritten after every pass.
  ProgressOptions po;
  po.verbose = verbose;
  po.terminal = isatty(STDERR_FILENO) != 0;
  po.columns = terminal_columns();
  if (const char* d = std::getenv("ANISURF_PROGRESS_DELAY"); d && *d) po.live_delay = std::atof(d);
  po.predicted_vertices = predicted_vertex_count(metric_complexity(control.mesh(), control.target_metric()));
  const remesh::PassReport initial = remesher.measure();
  const int inverted_before = adapted.count_inverted();
  std::vector<remesh::PassReport> passes;
  double run_seconds = 0;
  {
    ProgressDisplay display(po, [](std::string_view text) {
      std::fwrite(text.data(), 1, text.size(), stderr);
      std::fflush(stderr);
    });
    const auto t_run = Clock::now();
    passes = remesher.run([&](const remesh::PassReport& r) {
      display.pass(r, std::chrono::duration<double>(Clock::now() - t_run).count());
    });
    display.finish();
    run_seconds = std::chrono::duration<double>(Clock::now() - t_run).count();
  }
  const remesh::PassReport final_state = remesher.measure();
  const int inverted = adapted.count_inverted();

  // Outputs: the mesh, its metric (and the solution values) in compact
  // numbering. T_1 is taken out and the G1 surface freed first: writing
  // copies the mesh once more, and the peak memory must not add up both.
  const std::string surface_name = geometry->name();
  SurfaceMesh t1 = std::move(adapted.mesh());  // `adapted` is not used after this
  geometry.reset();
  t1.compact();
  const Property<SymTensor3> t1_metric = t1.get_vertex_property<SymTensor3>("remesh:metric");
  save_mesh(out, t1);
  const std::string out_sol = sol_path_for(out);
  std::vector<FieldData> fields;
  FieldData mf;
  mf.info = FieldInfo{"metric", FieldKind::Tensor, 6};
  for (int v = 0; v < t1.vertex_capacity(); ++v) {
    const SymTensor3& T = t1_metric[Vertex(v)];
    mf.values.insert(mf.values.end(), T.m.begin(), T.m.end());
  }
  fields.push_back(std::move(mf));
  std::vector<FieldData> interpolated;  // --interpolate's fields, to OUT.fields.sol
  for (const FieldInfo& info : control.field_infos()) {
    FieldData f;
    f.info = info;
    const Property<FieldValue> prop = t1.get_field(info.name);
    for (int v = 0; v < t1.vertex_capacity(); ++v)
      f.values.insert(f.values.end(), prop[Vertex(v)].begin(), prop[Vertex(v)].begin() + info.ncomp);
    (info.name.rfind(kInterpolatedPrefix, 0) == 0 ? interpolated : fields).push_back(std::move(f));
  }
  write_sol(out_sol, fields, t1.vertex_capacity(), 3);
  const std::string out_fields = interpolated.empty() ? std::string() : fields_path_for(out);
  if (!interpolated.empty()) write_sol(out_fields, interpolated, t1.vertex_capacity(), 3);
  const double seconds = std::chrono::duration<double>(Clock::now() - t_start).count();

  int splits = 0, collapses = 0, swaps = 0, moves = 0, removed = 0;
  for (const auto& r : passes) {
    splits += r.splits;
    collapses += r.collapses;
    swaps += r.swaps;
    moves += r.moves;
    removed += r.removed_vertices;
  }
  if (!report_path.empty()) {
    nlohmann::json j;
    j["input"] = in;
    j["output"] = out;
    j["metric"] = what;
    j["surface"] = surface_name;
    j["seconds"] = seconds;
    j["setup_seconds"] = t_setup;
    j["initial"] = pass_json(initial);
    j["final"] = pass_json(final_state);
    j["inverted"] = inverted;
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : passes) arr.push_back(pass_json(r));
    j["passes"] = arr;
    AtomicFile f(report_path);
    f.stream() << j.dump(1) << "\n";
    f.commit();
  }
  std::printf("                 input      output\n");
  std::printf("vertices     %9d   %9d   (the metric predicts ~%.0f: 2 C / sqrt 3)\n", initial.vertices,
              final_state.vertices, po.predicted_vertices);
  std::printf("triangles    %9d   %9d\n", initial.triangles, final_state.triangles);
  std::printf("in band      %8.1f%%   %8.1f%%   (edges with metric length in [0.71, 1.41])\n",
              100 * initial.in_band_share, 100 * final_state.in_band_share);
  std::printf("length       %9.3f   %9.3f   (min)\n", initial.length_min, final_state.length_min);
  std::printf("             %9.3f   %9.3f   (max)\n", initial.length_max, final_state.length_max);
  std::printf("c_K min      %9.3f   %9.3f   (eq. 17)\n", initial.q_min, final_state.q_min);
  std::printf("c_K mean     %9.3f   %9.3f\n", initial.q_mean, final_state.q_mean);
  std::printf("inverted     %9d   %9d   (triangles facing against the surface normal)\n", inverted_before, inverted);
  std::printf("operations   %d splits, %d collapses, %d swaps, %d moves, %d removed (valence < 4)\n", splits,
              collapses, swaps, moves, removed);
  std::printf("remeshing    %.2f s, %s operations per second\n", run_seconds,
              format_rate(splits + collapses + swaps + moves + removed, run_seconds).c_str());
  std::printf("written      %s, %s%s%s (%.2f s)\n", out.c_str(), out_sol.c_str(), out_fields.empty() ? "" : ", ",
              out_fields.c_str(), seconds);
  return 0;
}

}  // namespace

Command adapt_command() {
  return {"adapt", "adapt a surface mesh to a metric (split, collapse, swap, smooth; report sections 5-6)",
          kAdaptHelp, run_adapt};
}

}  // namespace anisurf::cli
