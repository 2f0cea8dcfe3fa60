// `anisurf adapt`: the remesher of the report's section 6 on a surface mesh
// and a metric (Mmg's mmgs spellings accepted).
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <optional>
#include <iostream>

#include <sys/ioctl.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/metric_options.h"
#include "cli/progress.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/parallel_chunks.h"
#include "io/mesh_io.h"
#include "metric/metric_field.h"
#include "metric/surface_metric.h"
#include "remesh/adapt.h"

namespace anisurf::cli {

namespace {

const char* kAdaptHelp =
    "usage: anisurf adapt IN.mesh METRIC [options] -o OUT.mesh\n"
    "\n"
    "Adapts the surface mesh IN to a metric (Castro-Diaz & Hecht 1995, sections 5-6):\n"
    "splits of edges longer than lmax, collapses of edges shorter than lmin, swaps on\n"
    "the quality of eq. 17, smoothing (eq. 19), the final optimisation. New and moved\n"
    "vertices are projected onto the input surface (T_G) and take their metric from\n"
    "the input mesh (T_0). Writes OUT.mesh and its metric OUT.sol (tensors); a .msh,\n"
    ".vtu, .vtp or .vtk output holds the metric (field \"metric\") and the fields itself.\n"
    "\n"
    "METRIC (one source, as in `anisurf metric`):\n"
    "  --sol S | -sol S     metric tensors or sizes on the vertices of IN\n"
    "  --metric-field NAME  the field NAME of IN itself (.msh $NodeData, .vtu/.vtp/.vtk\n"
    "                       point data): a 3x3 tensor or a size; with no other\n"
    "                       source such an IN's field \"metric\", else its first tensor\n"
    "                       field, is used\n"
    "  --size EXPR          isotropic size h(x,y,z)\n"
    "  --tensor EXPR        'm11, m12, m22, m13, m23, m33'\n"
    "  --hessian-of EXPR    with --error EPS | --complexity C | --vertices N [--norm P]\n"
    "                       (the L^p-optimal metric, p = 2 by default; see `anisurf\n"
    "                       metric --help`)\n"
    "                       (a vertex count or complexity is met after bounds and\n"
    "                       gradation)\n"
    "  --hessian-of-field NAME  the same with the solution field NAME of --interpolate's\n"
    "                       file (sol0, sol1 ... or the names the file gives)\n"
    "  --curvature          geometric metric from --hausd alone\n"
    "  --hmin A --hmax B    size bounds (also -hmin -hmax); --max-aniso K\n"
    "options:\n"
    "  --hausd D            chordal deviation: the metric is intersected with the\n"
    "                       curvature metric of D (also -hausd); new vertices stay\n"
    "                       within D / 5 of the input surface and feature curves sag\n"
    "                       by D at most; at the end, edge midpoints and triangle\n"
    "                       centroids farther than D from the input are split onto it.\n"
    "                       Without --hausd, a metric from a .sol, a field, --tensor or\n"
    "                       a Hessian gets D = diagonal / 1000 (geometry protection,\n"
    "                       printed). --size or --iso: the size is met, and edge\n"
    "                       midpoints and centroids farther from the input than 0.1 x\n"
    "                       the size are split onto it. --hausd 0: none.\n"
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
    "                       the projection onto the input triangles; g1-closest: its\n"
    "                       closest point (slower); polyhedral; auto (default): g1,\n"
    "                       or polyhedral for a coarsening (no input edge longer than\n"
    "                       1.4 in the metric) whose smooth surface would lie within\n"
    "                       0.05 h (and hausd / 2) of the input's facets\n"
    "  --weld TOL           merge the vertices closer than TOL x the bounding box\n"
    "                       diagonal, in every format (0: identical positions; a soup\n"
    "                       of triangles becomes one surface)\n"
    "  --free-surface       new vertices follow the G1 surface wherever it goes; by\n"
    "                       default they stay near the input's triangles (within 1/20\n"
    "                       of the size, or the sag a smooth surface through them has;\n"
    "                       --hausd D: D / 5), which on a coarse smooth input (the\n"
    "                       report's section 7.2) keeps them partly on its facets\n"
    "  --geometry G         T_G: another mesh of the surface to project onto (e.g. a\n"
    "                       finer one); IN stays T_0, the metric's support\n"
    "  --rounds N           at most N rounds of split/collapse/swap/smooth per stage\n"
    "                       (default 30; --iterations N is the same option)\n"
    "  --cycles N           section 7.1's loop: the output becomes the next input and\n"
    "                       the metric is derived again on it (an expression evaluated\n"
    "                       anew, a field carried over), at most N times; stops at a\n"
    "                       fixed point (vertex count within --fixed-point, default\n"
    "                       0.02, of the previous cycle's). One line per cycle.\n"
    "  --curve-turn DEG     collapses and moves along feature curves: largest turn\n"
    "                       between the new and old segments where the curve bends\n"
    "                       (default 25)\n"
    "  --curve-sag S        ... and largest distance of a new segment from the G1\n"
    "                       feature curve, relative to the size the metric asks for\n"
    "                       along it (default 0.1; a straight curve coarsens freely,\n"
    "                       an arc of radius r to sizes of 8 S r), and at most the\n"
    "                       chordal deviation --hausd)\n"
    "  --crease-keep F      a feature edge of the output keeps at least F of the\n"
    "                       dihedral angle of the input's crease under it: where it\n"
    "                       keeps less (the triangles beside it reach past a crease\n"
    "                       narrower than the size), the triangle turned farthest\n"
    "                       from the input is split towards the crease, onto the\n"
    "                       input (default 0.6; 0: off)\n"
    "  --repair-quality Q   the final pass removes a vertex of a triangle of quality\n"
    "                       below Q into a neighbour where the triangles replacing\n"
    "                       its fan are better (a vertex squeezed between others,\n"
    "                       its edges at lmin; default 0.8; 0: off)\n"
    "  --relocate-quality Q then moves each free vertex of a triangle of quality\n"
    "                       below Q where the worst triangle of its fan is best\n"
    "                       (a search in its tangent plane; the fan's summed\n"
    "                       quality does not fall, below 0.8 by no more than the\n"
    "                       worst gains; no edge below lmin gets shorter; where\n"
    "                       the metric jumps, a triangle across the jump only\n"
    "                       keeps its quality; default 0.9; 0: off)\n"
    "  --strip-width W      needles that no operator avoids do not hold back the\n"
    "                       collapses and moves near them: triangles across a strip\n"
    "                       between feature curves narrower than W in the metric (a\n"
    "                       blunt trailing edge, the side of a thin plate: one layer\n"
    "                       of needles along it) and triangles on an edge shorter\n"
    "                       than lmin between two corners (default 0.5; 0: off)\n"
    "  --max-memory MB      refuse, before any pass, a metric whose predicted output\n"
    "                       needs more (about 400 bytes per predicted vertex; default:\n"
    "                       the machine's memory)\n"
    "  --max-growth K       stop (error, nothing written) when the mesh grows past K x\n"
    "                       the predicted vertices + the input's: a metric the\n"
    "                       surface's curvature cannot carry (default 8; 0: no limit)\n"
    "  --threads N          threads (default 0: all cores): the mesh is remeshed as N\n"
    "                       regions at once, then the band around their borders; the\n"
    "                       output depends on N, not on the timing (1: serial)\n"
    "  --relax N            Remark 6: adapt first to N relaxed metrics between the\n"
    "                       input mesh's sizes and the target (default 0: off)\n"
    "  --report FILE        per-pass report (JSON)\n"
    "  --interpolate F.sol  a solution on IN's vertices (any fields), interpolated onto\n"
    "                       the output from T_0 (section 6); written to OUT.fields.sol\n"
    "                       (or into OUT for .msh .vtu .vtp .vtk)\n"
    "  -v N                 verbosity on stderr: 0 quiet, 1 per round (default), 2 per\n"
    "                       pass; at 1 on a terminal, a live line (round, pass, counts,\n"
    "                       vertices against the metric's prediction, op/s) after each pass\n"
    "                       once the run has lasted ANISURF_PROGRESS_DELAY s (default 0.5)\n"
    "  -o OUT | -out OUT    output mesh (required); the metric goes to OUT.sol\n"
    "\n"
    "examples:\n"
    "  anisurf adapt sphere.mesh -sol sphere_iso.sol -o out.mesh\n"
    "  mmgs-style: anisurf adapt -in sphere.mesh -sol band.sol -hgrad -1 -out out.mesh\n"
    "  anisurf adapt square.mesh --hessian-of \"100*x^2\" --error 0.01 --cycles 6 -hgrad -1 -o sq.mesh\n";

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
  j["round"] = r.round;
  j["splits"] = r.splits;
  j["collapses"] = r.collapses;
  j["swaps"] = r.swaps;
  j["moves"] = r.moves;
  j["removed_vertices"] = r.removed_vertices;
  j["split_unprojected"] = r.split_unprojected;
  j["bound_splits"] = r.bound_splits;
  j["beyond_bound"] = r.beyond_bound;
  j["crease_splits"] = r.crease_splits;
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
  j["region"] = r.region;
  j["touched"] = r.touched.size();
  return j;
}

// The options of `anisurf adapt` as the engine's AdaptOptions (the metric
// recipe is completed once the files are read).
struct AdaptCommandLine {
  std::string in, out, geometry, report, interpolate;
  BuildOptions build;  // --weld
  MetricSourceOptions metric;
  // The metric is a field of IN itself (--metric-field, or a format with
  // fields inside and no other source): its name, empty for "metric" or the
  // first tensor field.
  bool metric_from_input = false;
  std::string metric_field;
  remesh::AdaptOptions options;
  double hausd = 0, hgrad = 1.3;
  int verbose = 1;
};

double option_either(ArgParser& p, const char* long_name, const char* mmg_name, double fallback) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double x = p.option_double(long_name, nan);
  return std::isnan(x) ? p.option_double(mmg_name, fallback) : x;
}

int int_option(ArgParser& p, const char* name, int fallback, int lowest, const char* what) {
  const double x = p.option_double(name, fallback);
  if (!(x >= lowest) || x != std::floor(x) || x > 1e6)
    throw UsageError{std::string(name) + " expects " + what + ", got " + std::to_string(x)};
  return static_cast<int>(x);
}

AdaptCommandLine parse_adapt(const std::vector<std::string>& args) {
  AdaptCommandLine c;
  ArgParser p(args);
  c.in = p.option("-in", "--input");
  c.out = p.option("-o", "--output");
  if (c.out.empty()) c.out = p.option("-out");
  c.metric = parse_metric_options(p);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.hausd = option_either(p, "--hausd", "-hausd", nan);
  c.hgrad = option_either(p, "--hgrad", "-hgrad", 1.3);
  remesh::AdaptOptions& o = c.options;
  o.features.ridge_angle_deg = option_either(p, "--ar", "-ar", 45.0);
  o.features.detect_ridges = !p.flag("--nr", "-nr");
  o.remesh.op.lmin = p.option_double("--lmin", o.remesh.op.lmin);
  o.remesh.op.lmax = p.option_double("--lmax", o.remesh.op.lmax);
  o.remesh.op.max_curve_turn_deg = p.option_double("--curve-turn", o.remesh.op.max_curve_turn_deg);
  o.remesh.op.curve_sag = p.option_double("--curve-sag", o.remesh.op.curve_sag);
  o.remesh.crease_keep = p.option_double("--crease-keep", o.remesh.crease_keep);
  o.remesh.repair_quality = p.option_double("--repair-quality", o.remesh.repair_quality);
  o.remesh.relocate_quality = p.option_double("--relocate-quality", o.remesh.relocate_quality);
  o.remesh.op.strip_width = p.option_double("--strip-width", o.remesh.op.strip_width);
  if (p.flag("--free-surface")) o.input_bound.enabled = false;
  o.remesh.max_rounds = int_option(p, "--iterations", o.remesh.max_rounds, 1, "a number of rounds >= 1");
  o.remesh.max_rounds = int_option(p, "--rounds", o.remesh.max_rounds, 1, "a number of rounds >= 1");
  o.remesh.relaxation_stages = int_option(p, "--relax", 0, 0, "a number of stages >= 0");
  o.cycles = int_option(p, "--cycles", 1, 1, "a number of cycles >= 1");
  o.threads = int_option(p, "--threads", 0, 0, "a number of threads >= 0 (0: all cores)");
  o.fixed_point = p.option_double("--fixed-point", o.fixed_point);
  const double max_memory_mb = p.option_double("--max-memory", 0);
  if (!(max_memory_mb >= 0)) throw UsageError{"--max-memory expects megabytes >= 0 (0: the machine's memory)"};
  o.memory_limit = max_memory_mb * 1e6;
  o.max_growth = p.option_double("--max-growth", o.max_growth);
  if (!(o.max_growth >= 0) || !std::isfinite(o.max_growth))
    throw UsageError{"--max-growth expects a factor >= 0 (0: no limit)"};
  const std::string length = p.option("--length");
  const std::string interpolation = p.option("--interpolation");
  const std::string surface = p.option("--surface");
  c.geometry = p.option("--geometry");
  c.build = weld_build_options(p);
  c.report = p.option("--report");
  c.interpolate = p.option("--interpolate");
  c.metric_field = p.option("--metric-field");
  c.metric_from_input = !c.metric_field.empty();
  o.remesh.record_touched = !c.report.empty();  // only the JSON report counts them
  const std::string verb = p.option("-v", "--verbose");
  c.verbose = verb.empty() ? 1 : std::atoi(verb.c_str());
  // Every pass's state is printed (-v 2) or written (--report); else the round's last one.
  o.remesh.measure_every_pass = c.verbose >= 2 || !c.report.empty();
  auto pos = p.positionals();
  if (c.in.empty() && !pos.empty()) {
    c.in = pos.front();
    pos.erase(pos.begin());
  }
  if (c.in.empty() || !pos.empty()) throw UsageError{"expected one input mesh"};
  if (c.out.empty()) throw UsageError{"-o OUT.mesh is required"};
  if (c.metric.source_count() + c.metric_from_input > 1) throw UsageError{"give at most one metric source"};
  if (c.metric.source_count() == 0 && !c.metric_from_input) {
    if (c.hausd > 0)
      c.metric.curvature = true;
    else if (format_embeds_fields(mesh_format_from_path(c.in)))
      c.metric_from_input = true;
    else
      throw UsageError{"give a metric source (--sol, --size, ...) or --hausd D"};
  }
  if (c.metric.curvature && !(c.hausd > 0)) throw UsageError{"--curvature needs --hausd D with D > 0"};
  if (!c.metric.hessian_of_field.empty() && c.interpolate.empty())
    throw UsageError{"--hessian-of-field NAME needs the solution: --interpolate F.sol"};
  if (!(o.remesh.op.lmin > 0) || !(o.remesh.op.lmax > o.remesh.op.lmin)) throw UsageError{"need 0 < lmin < lmax"};
  if (!(o.remesh.op.max_curve_turn_deg > 0) || !(o.remesh.op.curve_sag > 0))
    throw UsageError{"--curve-turn and --curve-sag expect numbers > 0"};
  if (!(o.remesh.crease_keep >= 0) || !(o.remesh.crease_keep <= 1))
    throw UsageError{"--crease-keep expects a share in [0, 1] (0: off)"};
  if (!(o.remesh.repair_quality >= 0) || !(o.remesh.repair_quality <= 1))
    throw UsageError{"--repair-quality expects a quality in [0, 1] (0: off)"};
  if (!(o.remesh.relocate_quality >= 0) || !(o.remesh.relocate_quality <= 1))
    throw UsageError{"--relocate-quality expects a quality in [0, 1] (0: off)"};
  if (!(o.remesh.op.strip_width >= 0)) throw UsageError{"--strip-width expects a metric length >= 0 (0: off)"};
  if (!(o.fixed_point >= 0)) throw UsageError{"--fixed-point expects a share >= 0"};
  if (length == "log")
    o.length = LengthFormula::LinearSize;
  else if (!length.empty() && length != "linear")
    throw UsageError{"--length expects linear or log, got '" + length + "'"};
  if (interpolation == "linear")
    o.interpolation = MetricInterpolation::Linear;
  else if (interpolation == "inverse")
    o.interpolation = MetricInterpolation::Inverse;
  else if (interpolation == "log")
    o.interpolation = MetricInterpolation::LogEuclidean;
  else if (!interpolation.empty() && interpolation != "size")
    throw UsageError{"--interpolation expects size, linear, inverse or log, got '" + interpolation + "'"};
  if (surface == "polyhedral")
    o.surface = remesh::SurfaceKind::Polyhedral;
  else if (surface == "g1-closest")
    o.surface = remesh::SurfaceKind::G1Closest;
  else if (surface == "g1")
    o.surface = remesh::SurfaceKind::G1;
  else if (!surface.empty() && surface != "auto")
    throw UsageError{"--surface expects auto, g1, g1-closest or polyhedral, got '" + surface + "'"};
  if (!(c.hgrad > 1) && c.hgrad != -1 && c.hgrad != 0 && c.hgrad != 1)
    throw UsageError{"--hgrad expects a ratio > 1, or -1 (off)"};
  return c;
}

// The input mesh with the solution fields of --interpolate (renamed with
// kInterpolatedPrefix, their names in *names) and the metric of -sol.
struct AdaptFiles {
  remesh::AdaptInput input;
  MetricField sol_metric;
  std::vector<std::string> interpolated_names;  // the names in the --interpolate file
};

// The metric carried by IN itself (AdaptCommandLine::metric_from_input): the
// field named --metric-field, else "metric", else the first tensor field;
// taken out of T_0's fields (it is not a solution to interpolate).
MetricField metric_of_input(const AdaptCommandLine& c, SurfaceMesh& t0, const BuildReport& report) {
  const std::string name = c.metric_field.empty() ? embedded_metric_name(t0) : c.metric_field;
  if (name.empty())
    throw MetricError(c.in + ": no metric: the file has no tensor field; give a metric source (--sol, --size, ...) "
                      "or --hausd D");
  std::string known;
  bool found = false;
  for (const FieldInfo& info : t0.fields()) {
    found = found || info.name == name;
    known += (known.empty() ? "" : ", ") + info.name;
  }
  if (!found)
    throw MetricError(c.in + ": no field '" + name + "' (--metric-field); the file's fields: " +
                      (known.empty() ? "none" : known));
  MetricField metric;
  try {
    metric = metric_from_field(t0, name, report.vertex_origin);
  } catch (const MetricError& e) {
    throw MetricError(c.in + ": field '" + name + "': " + e.what());
  }
  t0.remove_field(name);
  return metric;
}

// The fields of a .sol read ahead (`ahead`, without the mesh's vertex
// count) when they have one value per vertex of the mesh file; else the
// file read again against that count, which throws its error with the line
// (a file that failed ahead fails the same way, or in its count first).
std::vector<FieldData> read_sol_for(const std::string& path, std::future<std::vector<FieldData>>& ahead,
                                    int mesh_vertices) {
  std::vector<FieldData> fields;
  try {
    fields = ahead.get();
  } catch (const std::exception&) {
    return read_sol(path, mesh_vertices);
  }
  bool counts_match = !fields.empty();
  for (const FieldData& d : fields)
    counts_match = counts_match && d.info.ncomp > 0 &&
                   d.values.size() == static_cast<std::size_t>(mesh_vertices) * static_cast<std::size_t>(d.info.ncomp);
  return counts_match ? fields : read_sol(path, mesh_vertices);
}

AdaptFiles read_adapt_inputs(AdaptCommandLine& c) {
  AdaptFiles f;
  BuildReport report;
  // A mesh + .sol pair whose writer was killed between its renames is
  // completed before it is read (never read half old, half new).
  for (const std::string& path : {c.in, c.metric.sol, c.interpolate})
    if (!path.empty()) finish_interrupted_commits(path);
  // The metric's .sol is read on a second thread while the mesh is (its
  // vertex count is checked once both are in).
  std::future<std::vector<FieldData>> early_sol;
  if (!c.metric.sol.empty() && available_threads() > 1)
    early_sol = std::async(std::launch::async, [path = c.metric.sol] { return read_sol(path); });
  f.input.mesh = load_mesh(c.in, &report, c.build);
  f.input.vertex_origin = report.vertex_origin;
  if (c.metric_from_input) f.sol_metric = metric_of_input(c, f.input.mesh, report);
  if (!c.metric.sol.empty()) {
    std::vector<FieldData> sol = early_sol.valid() ? read_sol_for(c.metric.sol, early_sol, report.input_vertices)
                                                   : read_sol(c.metric.sol, report.input_vertices);
    // The metric is read into its own array; T_0 keeps no copy as a field.
    // It is attached to T_0 for the conversion and removed after, or to a
    // copy of T_0 when T_0 has fields of the same names (from its own file).
    bool names_taken = false;
    for (const FieldData& d : sol) names_taken = names_taken || f.input.mesh.get_field(d.info.name);
    std::optional<SurfaceMesh> copy;
    if (names_taken) copy = f.input.mesh;
    SurfaceMesh& with_fields = copy ? *copy : f.input.mesh;
    attach_fields(with_fields, sol, report);
    auto detach = [&] {
      if (!copy)
        for (const FieldData& d : sol) f.input.mesh.remove_field(d.info.name);
    };
    try {
      f.sol_metric = metric_from_field(with_fields, {}, report.vertex_origin);
    } catch (const MetricError& e) {
      detach();
      throw MetricError(c.metric.sol + ": " + e.what());
    }
    detach();
  }
  // Section 6: a solution given on IN's vertices, interpolated onto the
  // adapted mesh from its location in T_0 (written to OUT.fields.sol).
  if (!c.interpolate.empty()) {
    auto fields = read_sol(c.interpolate, report.input_vertices);
    std::string field_name;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      f.interpolated_names.push_back(fields[k].info.name);
      if (fields[k].info.name == c.metric.hessian_of_field) field_name = kInterpolatedPrefix + std::to_string(k);
      fields[k].info.name = kInterpolatedPrefix + std::to_string(k);
    }
    if (!c.metric.hessian_of_field.empty() && field_name.empty()) {
      std::string names;
      for (const auto& n : f.interpolated_names) names += (names.empty() ? "" : ", ") + n;
      throw UsageError{"--hessian-of-field: no field '" + c.metric.hessian_of_field + "' in " + c.interpolate +
                       " (its fields: " + names + ")"};
    }
    c.metric.hessian_of_field = field_name;
    attach_fields(f.input.mesh, fields, report);
  }
  return f;
}

// True when OUT's format carries fields inside (.msh .vtu .vtp .vtk): the
// metric and the interpolated fields go into OUT itself, not into .sol files.
bool embeds_fields(const std::string& out) { return format_embeds_fields(mesh_format_from_path(out)); }

// The adapted mesh with the metric, --interpolate's fields and the other
// fields the mesh carried through adaptation (those of IN's own file; a
// field named "metric" among them is replaced by the adapted metric).
MeshData mesh_with_fields(const SurfaceMesh& t1, std::vector<FieldData> metric, std::vector<FieldData> interpolated) {
  MeshData d = to_mesh_data(t1);
  std::vector<FieldData> fields = std::move(metric);
  for (FieldData& f : interpolated) fields.push_back(std::move(f));
  for (FieldData& f : d.fields)
    if (f.info.name.rfind(kInterpolatedPrefix, 0) != 0 && f.info.name != "metric") fields.push_back(std::move(f));
  d.fields = std::move(fields);
  return d;
}

// OUT.mesh, OUT.sol (the metric: Mmg reads it) and OUT.fields.sol
// (--interpolate's fields), written as one set: all or none replaced; or,
// for a format with fields inside, OUT alone. Consumes r's mesh and metric
// (freed as soon as they are written: the output's peak memory).
void write_adapt_outputs(const AdaptCommandLine& c, remesh::AdaptResult& r,
                         const std::vector<std::string>& interpolated_names, std::string* fields_path) {
  const SurfaceMesh& t1 = r.mesh;
  const int n_vertices = t1.vertex_capacity();
  OutputSet outputs;
  std::vector<FieldData> interpolated;
  for (const FieldInfo& info : t1.fields()) {
    if (info.name.rfind(kInterpolatedPrefix, 0) != 0) continue;
    FieldData f;
    f.info = info;
    f.info.name = interpolated_names.at(std::stoul(info.name.substr(std::string(kInterpolatedPrefix).size())));
    const Property<FieldValue> prop = t1.get_field(info.name);
    for (int v = 0; v < n_vertices; ++v)
      f.values.insert(f.values.end(), prop[Vertex(v)].begin(), prop[Vertex(v)].begin() + info.ncomp);
    interpolated.push_back(std::move(f));
  }
  if (embeds_fields(c.out)) {
    std::vector<FieldData> metric(1);
    FieldData& mf = metric.front();
    mf.info = FieldInfo{"metric", FieldKind::Tensor, 6};
    mf.values.reserve(6 * static_cast<std::size_t>(n_vertices));
    for (int v = 0; v < n_vertices; ++v) mf.values.insert(mf.values.end(), r.metric[v].m.begin(), r.metric[v].m.end());
    write_mesh_data(outputs.temporary(c.out), mesh_with_fields(t1, std::move(metric), std::move(interpolated)));
    outputs.commit();
    return;
  }
  // The mesh, its metric and the fields are independent files: formatted
  // and written at once, one thread each (the numbers' text is most of it),
  // when --threads allows two. The metric is written from its tensors in
  // place (six doubles each).
  static_assert(sizeof(SymTensor3) == 6 * sizeof(double), "a MetricField is read as 6 doubles per vertex");
  const std::vector<FieldView> metric = {
      FieldView{FieldInfo{"metric", FieldKind::Tensor, 6}, r.metric.empty() ? nullptr : r.metric.front().m.data(),
                6 * r.metric.size()}};
  const std::string mesh_tmp = outputs.temporary(c.out), sol_tmp = outputs.temporary(sol_path_for(c.out));
  std::string fields_tmp;
  if (!interpolated.empty()) {
    *fields_path = fields_path_for(c.out);
    fields_tmp = outputs.temporary(*fields_path);
  }
  auto sol = std::async(available_threads() > 1 ? std::launch::async : std::launch::deferred, [&] {
    write_sol(sol_tmp, metric, n_vertices, 3);
    r.metric = MetricField();
    if (!fields_tmp.empty()) write_sol(fields_tmp, interpolated, n_vertices, 3);
  });
  try {
    // The mesh's fields are written apart (OUT.fields.sol): the data goes
    // without them, and T_1's memory is freed before the text is formatted.
    for (const FieldInfo& info : std::vector<FieldInfo>(r.mesh.fields())) r.mesh.remove_field(info.name);
    const MeshData data = to_mesh_data(std::move(r.mesh));
    write_mesh_data(mesh_tmp, data);
  } catch (...) {
    sol.wait();  // the temporaries are removed with the set, after the writer is done
    throw;
  }
  sol.get();
  outputs.commit();
}

void write_report(const AdaptCommandLine& c, const remesh::AdaptResult& r) {
  nlohmann::json j;
  j["input"] = c.in;
  j["output"] = c.out;
  j["metric"] = r.cycles.front().metric;
  j["surface"] = r.surface;
  j["seconds"] = r.seconds;
  j["setup_seconds"] = r.cycles.front().setup_seconds;
  j["initial"] = pass_json(r.cycles.front().initial);
  j["final"] = pass_json(r.cycles.back().final);
  j["inverted"] = r.cycles.back().inverted_after;
  nlohmann::json arr = nlohmann::json::array(), cycles = nlohmann::json::array();
  for (const auto& cycle : r.cycles) {
    for (const auto& pass : cycle.passes) arr.push_back(pass_json(pass));
    nlohmann::json cj;
    cj["cycle"] = cycle.cycle;
    cj["metric"] = cycle.metric;
    cj["predicted_vertices"] = cycle.predicted_vertices;
    cj["complexity"] = cycle.complexity;
    cj["vertices"] = cycle.final.vertices;
    cj["triangles"] = cycle.final.triangles;
    cj["in_band_pct"] = 100.0 * cycle.final.in_band_share;
    if (!std::isnan(cycle.error_estimate)) cj["error_estimate"] = cycle.error_estimate;
    cycles.push_back(cj);
  }
  j["passes"] = arr;
  j["cycles"] = cycles;
  j["fixed_point"] = r.fixed_point;
  AtomicFile f(c.report);
  f.stream() << j.dump(1) << "\n";
  f.commit();
}

void print_summary(const AdaptCommandLine& c, int cycles, const remesh::AdaptResult& r,
                   const std::string& fields_path) {
  const remesh::PassReport& initial = r.cycles.front().initial;
  const remesh::PassReport& final_state = r.cycles.back().final;
  int splits = 0, collapses = 0, swaps = 0, moves = 0, removed = 0;
  double run_seconds = 0;
  for (const auto& cycle : r.cycles) {
    run_seconds += cycle.remesh_seconds;
    for (const auto& p : cycle.passes) {
      splits += p.splits;
      collapses += p.collapses;
      swaps += p.swaps;
      moves += p.moves;
      removed += p.removed_vertices;
    }
  }
  std::printf("                 input      output\n");
  std::printf("vertices     %9d   %9d   (the metric predicts ~%.0f)\n", initial.vertices,
              final_state.vertices, r.cycles.back().predicted_vertices);
  std::printf("triangles    %9d   %9d\n", initial.triangles, final_state.triangles);
  std::printf("in band      %8.1f%%   %8.1f%%   (edges with metric length in [0.71, 1.41])\n",
              100 * initial.in_band_share, 100 * final_state.in_band_share);
  std::printf("length       %9.3f   %9.3f   (min)\n", initial.length_min, final_state.length_min);
  std::printf("             %9.3f   %9.3f   (max)\n", initial.length_max, final_state.length_max);
  std::printf("c_K min      %9.3f   %9.3f   (eq. 17)\n", initial.q_min, final_state.q_min);
  std::printf("c_K mean     %9.3f   %9.3f\n", initial.q_mean, final_state.q_mean);
  std::printf("inverted     %9d   %9d   (triangles facing against the surface normal)\n",
              r.cycles.front().inverted_before, r.cycles.back().inverted_after);
  if (r.cycles.size() > 1 || cycles > 1)
    std::printf("cycles       %zu of %d%s\n", r.cycles.size(), cycles,
                r.fixed_point ? " (fixed point: the vertex count changed by less than the tolerance)" : "");
  std::printf("operations   %d splits, %d collapses, %d swaps, %d moves, %d removed (valence < 4)\n", splits,
              collapses, swaps, moves, removed);
  const double hausd = c.hausd > 0 ? c.hausd : r.protection_hausd;
  if ((hausd > 0 || r.size_protection > 0) && !r.cycles.back().passes.empty()) {
    // The final passes: one, or one per region and the band (--threads).
    int bound_splits = 0, beyond = 0;
    for (const auto& p : r.cycles.back().passes)
      if (p.kind == remesh::PassKind::Final) {
        bound_splits += p.bound_splits;
        beyond += p.beyond_bound;
      }
    char bound[96];
    if (hausd > 0)
      std::snprintf(bound, sizeof bound, "hausd %.4g", hausd);
    else
      std::snprintf(bound, sizeof bound, "%g x the size", r.size_protection);
    std::printf("distance     %d splits onto the input; %d edge midpoints or centroids farther than %s\n",
                bound_splits, beyond, bound);
  }
  int crease_splits = 0;
  for (const auto& p : r.cycles.back().passes)
    if (p.kind == remesh::PassKind::Final) crease_splits += p.crease_splits;
  if (crease_splits > 0)
    std::printf("creases      %d splits towards creases of the input (--crease-keep %g)\n", crease_splits,
                c.options.remesh.crease_keep);
  std::printf("remeshing    %.2f s, %s operations per second\n", run_seconds,
              format_rate(splits + collapses + swaps + moves + removed, run_seconds).c_str());
  if (embeds_fields(c.out))
    std::printf("written      %s, with the metric and fields inside (%.2f s)\n", c.out.c_str(), r.seconds);
  else
    std::printf("written      %s, %s%s%s (%.2f s)\n", c.out.c_str(), sol_path_for(c.out).c_str(),
                fields_path.empty() ? "" : ", ", fields_path.c_str(), r.seconds);
}

// One line per cycle on stderr (-v >= 1 with --cycles > 1).
void print_cycle(const remesh::CycleReport& cycle) {
  std::fprintf(stderr, "cycle %d: %d vertices, %d triangles, complexity %.4g (predicted %.0f), %.1f%% in band",
               cycle.cycle, cycle.final.vertices, cycle.final.triangles, cycle.complexity, cycle.predicted_vertices,
               100.0 * cycle.final.in_band_share);
  if (!std::isnan(cycle.error_estimate)) std::fprintf(stderr, ", estimated error %.4g", cycle.error_estimate);
  std::fprintf(stderr, "\n");
}

int run_adapt(const std::vector<std::string>& args) {
  AdaptCommandLine c = parse_adapt(args);
  check_writable(c.out);
  if (!embeds_fields(c.out)) check_writable(sol_path_for(c.out));
  // Temporaries of earlier runs into the same outputs that were killed.
  for (const std::string& path : {c.out, sol_path_for(c.out), fields_path_for(c.out)}) remove_stale_temporaries(path);
  const auto t_read = std::chrono::steady_clock::now();
  AdaptFiles files = read_adapt_inputs(c);
  c.options.metric = metric_recipe(c.metric, std::move(files.sol_metric), c.hausd, c.hgrad);
  if (c.hausd == 0) c.options.protect_fraction = 0;  // --hausd 0: no geometry protection
  SurfaceMesh separate_geometry;
  if (!c.geometry.empty()) {
    separate_geometry = load_mesh(c.geometry);
    files.input.geometry = &separate_geometry;
  }
  const SurfaceMesh& tg = files.input.geometry ? *files.input.geometry : files.input.mesh;
  const double protection = c.hausd > 0 ? 0 : remesh::effective_hausd(c.options, tg.bbox().diagonal());
  if (protection > 0 && c.verbose >= 1)
    std::fprintf(stderr,
                 "adapt: geometry protection: the metric is intersected with the curvature metric of hausd %.4g "
                 "(%g x the bounding-box diagonal; --hausd D to choose it, --hausd 0: off)\n",
                 protection, c.options.protect_fraction);
  const double size_protection = remesh::size_protection_of(c.options);
  if (size_protection > 0 && c.verbose >= 1)
    std::fprintf(stderr,
                 "adapt: geometry protection: edge midpoints and centroids farther from the input than %g x the "
                 "size (beyond the smooth surface's own sagitta) are split onto it (--hausd D for a bound, "
                 "--hausd 0: off)\n",
                 size_protection);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_read).count();
  const int verbose = c.verbose;
  const int cycles = c.options.cycles;
  if (verbose >= 2) std::fprintf(stderr, "  setup: %-45s %.2f s\n", "read the mesh", read_seconds);

  // Progress on stderr (cli/progress.h): one line per round (-v 1) or per pass
  // (-v 2); on a terminal, a live line below them rewritten after every pass.
  ProgressOptions po;
  po.verbose = verbose;
  po.terminal = isatty(STDERR_FILENO) != 0;
  po.columns = terminal_columns();
  if (const char* d = std::getenv("ANISURF_PROGRESS_DELAY"); d && *d) po.live_delay = std::atof(d);
  std::unique_ptr<ProgressDisplay> display;
  std::chrono::steady_clock::time_point t_run;
  const std::string in = c.in;
  remesh::AdaptCallbacks cb;
  cb.setup_step = [verbose](const std::string& step, double seconds) {
    if (verbose >= 2) std::fprintf(stderr, "  setup: %-45s %.2f s\n", step.c_str(), seconds);
  };
  cb.cycle_started = [&](const remesh::CycleReport& cycle) {
    if (verbose >= 1)
      std::fprintf(stderr, "adapt: %s: %d vertices, %d triangles; metric %s%s (%.2f s)\n", in.c_str(),
                   cycle.initial.vertices, cycle.initial.triangles, cycle.metric.c_str(),
                   cycles > 1 ? (", cycle " + std::to_string(cycle.cycle)).c_str() : "",
                   cycle.setup_seconds);
    po.predicted_vertices = cycle.predicted_vertices;
    display = std::make_unique<ProgressDisplay>(po, [](std::string_view text) {
      std::fwrite(text.data(), 1, text.size(), stderr);
      std::fflush(stderr);
    });
    t_run = std::chrono::steady_clock::now();
  };
  cb.pass = [&](const remesh::PassReport& r) {
    display->pass(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_run).count());
  };
  cb.cycle_ended = [&](const remesh::CycleReport& cycle) {
    display->finish();
    display.reset();
    if (verbose >= 1 && cycles > 1) print_cycle(cycle);
  };
  // The options go to the engine (a -sol metric is moved, not copied); the
  // summary needs only their cycle count.
  remesh::AdaptResult result = remesh::adapt(std::move(files.input), std::move(c.options), cb);

  std::string fields_path;
  write_adapt_outputs(c, result, files.interpolated_names, &fields_path);
  if (!c.report.empty()) write_report(c, result);
  print_summary(c, cycles, result, fields_path);
  return 0;
}

}  // namespace

Command adapt_command() {
  return {"adapt", "adapt a surface mesh to a metric (split, collapse, swap, smooth; report sections 5-6)",
          kAdaptHelp, run_adapt};
}

}  // namespace anisurf::cli
