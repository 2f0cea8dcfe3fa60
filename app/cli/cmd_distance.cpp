// `anisurf distance`: how far an output mesh lies from its input surface.
#include <nlohmann/json.hpp>

#include <chrono>
#include <future>
#include <cstdio>
#include <iostream>

#include "cli/cli.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "locate/surface_distance.h"

namespace anisurf::cli {

namespace {

const char* kDistanceHelp =
    "usage: anisurf distance REF OUT [--weld TOL] [--threads N] [--json]\n"
    "\n"
    "Measures the distance from the surface mesh OUT (e.g. an adapted mesh) to the\n"
    "reference surface mesh REF (e.g. its input) at OUT's vertices, edge midpoints and\n"
    "triangle centroids: for each sample, the exact distance to the closest point of\n"
    "REF's triangles. Prints OUT's vertex and triangle counts, the maximum and mean\n"
    "distance of each kind of sample, in REF's units and as a percentage of REF's\n"
    "bounding box diagonal, and where the largest distance is (the sample, its\n"
    "element numbered as in OUT's file, and its closest point on REF). The figures are\n"
    "those of ../shared/bench/surfdist.py. Both files in any format anisurf reads\n"
    "(.mesh .meshb .obj .off .ply .stl .gltf .glb .msh .vtu .vtp .vtk).\n"
    "\n"
    "options:\n"
    "  --weld TOL    merge vertices closer than TOL x the bounding box diagonal in both\n"
    "                meshes (as `anisurf info --weld`; default 0: identical positions)\n"
    "  --threads N   threads for the midpoints and centroids (default: all cores)\n"
    "  --json        print one JSON object instead of text\n"
    "\n"
    "example: anisurf distance falcon.mesh falcon.o.mesh\n";

// Seconds in all (reading, the locator, the measure) and of the measure alone.
struct Timing {
  double total = 0;
  double measure = 0;
};

// A mesh as read, with the numbering of its file.
struct Input {
  SurfaceMesh mesh;
  BuildReport report;
};

Input read_input(const std::string& path, double weld) {
  BuildOptions o;
  o.merge_tolerance = weld;
  Input in;
  in.mesh = load_mesh(path, &in.report, o);
  return in;
}

// 1-based number of a mesh vertex / triangle in its file.
int file_vertex(const Input& in, Vertex v) {
  const auto& origin = in.report.vertex_origin;
  return (v.idx >= 0 && v.idx < static_cast<int>(origin.size()) ? origin[static_cast<std::size_t>(v.idx)] : v.idx) + 1;
}
int file_triangle(const Input& in, int t) {
  const auto& origin = in.report.triangle_origin;
  return (t >= 0 && t < static_cast<int>(origin.size()) ? origin[static_cast<std::size_t>(t)] : t) + 1;
}

// The element of OUT holding the worst sample, as a user finds it in the file:
// "vertex 12", "edge 12-40", "triangle 7".
std::string worst_element_name(const Input& out, DistanceSample kind, int element) {
  if (element < 0) return "none";
  switch (kind) {
    case DistanceSample::Vertex: return "vertex " + std::to_string(file_vertex(out, Vertex(element)));
    case DistanceSample::Midpoint: {
      const Corner c(element);
      return "edge " + std::to_string(file_vertex(out, out.mesh.edge_from(c))) + "-" +
             std::to_string(file_vertex(out, out.mesh.edge_to(c)));
    }
    case DistanceSample::Centroid: return "triangle " + std::to_string(file_triangle(out, element));
  }
  return "?";
}

nlohmann::json point_json(const Vec3& p) { return {p.x, p.y, p.z}; }

nlohmann::json stats_json(const SurfaceDistance& d, const DistanceStats& s) {
  return {{"count", s.count},
          {"max", s.max},
          {"mean", s.mean},
          {"max_percent", d.percent(s.max)},
          {"mean_percent", d.percent(s.mean)}};
}

nlohmann::json distance_json(const std::string& ref, const std::string& out_path, const Input& out,
                             const SurfaceDistance& d, const Timing& timing) {
  const DistanceSample w = d.worst_sample();
  const DistanceStats& ws = d.stats(w);
  nlohmann::json j;
  j["reference"] = ref;
  j["mesh"] = out_path;
  j["V"] = d.vertices.count;
  j["T"] = d.centroids.count;
  j["reference_diagonal"] = d.reference_diagonal;
  j["vertices"] = stats_json(d, d.vertices);
  j["midpoints"] = stats_json(d, d.midpoints);
  j["centroids"] = stats_json(d, d.centroids);
  // The names of surfdist.py, for scripts that read both.
  j["vert_max"] = d.vertices.max;
  j["vert_mean"] = d.vertices.mean;
  j["mid_max"] = d.midpoints.max;
  j["mid_mean"] = d.midpoints.mean;
  j["cen_max"] = d.centroids.max;
  j["cen_mean"] = d.centroids.mean;
  j["max"] = d.max();
  j["max_percent"] = d.percent(d.max());
  j["worst"] = {{"sample", distance_sample_name(w)},
                {"element", worst_element_name(out, w, ws.worst_element)},
                {"position", point_json(ws.worst)},
                {"closest", point_json(ws.worst_closest)},
                {"distance", ws.max}};
  j["seconds"] = timing.total;
  j["measure_seconds"] = timing.measure;
  return j;
}

void print_distance_text(const std::string& ref, const Input& reference, const std::string& out_path,
                         const SurfaceDistance& d, const Input& out, const Timing& timing) {
  char buf[512];
  auto& o = std::cout;
  std::snprintf(buf, sizeof buf, "reference   %s: %d vertices, %d triangles, bounding box diagonal %.6g\n", ref.c_str(),
                reference.mesh.n_vertices(), reference.mesh.n_triangles(), d.reference_diagonal);
  o << buf;
  std::snprintf(buf, sizeof buf, "mesh        %s: V %d  T %d\n", out_path.c_str(), d.vertices.count, d.centroids.count);
  o << buf;
  o << "distance to the reference          max                     mean\n";
  auto row = [&](const char* name, const DistanceStats& s) {
    std::snprintf(buf, sizeof buf, "  %-10s (%7d)   %-12.6g (%8.4f%%)   %-12.6g (%8.4f%%)\n", name, s.count, s.max,
                  d.percent(s.max), s.mean, d.percent(s.mean));
    o << buf;
  };
  row("vertices", d.vertices);
  row("midpoints", d.midpoints);
  row("centroids", d.centroids);
  const DistanceSample w = d.worst_sample();
  const DistanceStats& ws = d.stats(w);
  std::snprintf(buf, sizeof buf, "worst       %.6g (%.4f%% of the diagonal) at the %s of %s\n", ws.max, d.percent(ws.max),
                distance_sample_name(w), worst_element_name(out, w, ws.worst_element).c_str());
  o << buf;
  std::snprintf(buf, sizeof buf, "            at (%.9g, %.9g, %.9g), closest point of the reference (%.9g, %.9g, %.9g)\n",
                ws.worst.x, ws.worst.y, ws.worst.z, ws.worst_closest.x, ws.worst_closest.y, ws.worst_closest.z);
  o << buf;
  std::snprintf(buf, sizeof buf, "time        %.3f s in all, of which measuring %.3f s (reading and the locator before)\n",
                timing.total, timing.measure);
  o << buf;
}

int run_distance(const std::vector<std::string>& args) {
  ArgParser p(args);
  const bool json = p.flag("--json");
  const double weld = p.option_double("--weld", 0.0);
  if (!(weld >= 0 && weld < 0.1)) throw UsageError{"--weld expects a tolerance relative to the bounding box in [0, 0.1)"};
  const double threads = p.option_double("--threads", 0.0);
  if (!(threads >= 0 && threads <= 1024) || threads != static_cast<int>(threads))
    throw UsageError{"--threads expects a whole number of threads (0: all cores)"};
  const auto pos = p.positionals();
  if (pos.size() != 2) throw UsageError{"expected REF and OUT"};
  const auto t0 = std::chrono::steady_clock::now();
  // OUT is read while REF is read and its locator built (on a large
  // reference, building the locator takes as long as reading a file).
  auto reading_out = std::async(std::launch::async, [&] { return read_input(pos[1], weld); });
  const Input reference = read_input(pos[0], weld);
  const Locator locator = distance_locator(reference.mesh);
  const Input out = reading_out.get();
  const auto t1 = std::chrono::steady_clock::now();
  SurfaceDistanceOptions o;
  o.threads = static_cast<int>(threads);
  const SurfaceDistance d = surface_distance(out.mesh, locator, o);
  const auto t2 = std::chrono::steady_clock::now();
  const Timing timing{std::chrono::duration<double>(t2 - t0).count(), std::chrono::duration<double>(t2 - t1).count()};
  if (json)
    std::cout << distance_json(pos[0], pos[1], out, d, timing).dump(2) << "\n";
  else
    print_distance_text(pos[0], reference, pos[1], d, out, timing);
  return 0;
}

}  // namespace

Command distance_command() {
  return {"distance", "distance of a mesh to a reference surface (vertices, midpoints, centroids)", kDistanceHelp,
          run_distance};
}

}  // namespace anisurf::cli
