// `anisurf reconstruct`: the G1 Bezier surface of report section 3, sampled
// by splitting every triangle into k^2.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli/cli.h"
#include "core/error.h"
#include "geometry/bezier_surface.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "geometry/sample.h"
#include "io/mesh_io.h"

namespace anisurf::cli {

namespace {

const char* kReconstructHelp =
    "usage: anisurf reconstruct MESH -o OUT [-k N] [options]\n"
    "\n"
    "Builds the smooth surface of the report's section 3 over MESH (Farin's G1\n"
    "Bezier surface: cubic patches from the vertex tangent planes, Clough-Tocher\n"
    "split, quartic elevation, G1 corrections across every edge that is not a\n"
    "feature; C0 along ridges, boundaries and reference interfaces) and writes it\n"
    "sampled: every triangle split into N^2 with its new vertices on the surface.\n"
    "Feature edges stay feature edges; references and tags are kept.\n"
    "\n"
    "options:\n"
    "  -o, --output OUT       output mesh (.mesh .meshb .obj .ply .stl .glb .msh .vtu .vtp .vtk)\n"
    "  -k N                   split factor (default 2: each triangle into 4)\n"
    "  --ridge-angle DEG      dihedral angle above which an edge is a ridge (default 45)\n"
    "  -nr, --no-ridges       no ridge detection (the file's Ridges are kept)\n"
    "  --corner-angle DEG     a curve turning by more than DEG at a vertex makes a corner (default 45)\n"
    "  --add-ridge I-J        tag the edge between vertices I and J (1-based) as a ridge (repeatable)\n"
    "  --remove-ridge I-J     untag it (repeatable)\n"
    "  --add-corner I         tag vertex I (1-based) as a corner (repeatable)\n"
    "  --remove-corner I      untag it (repeatable)\n"
    "  --normals fit|angle    vertex tangent planes: local height-function fit over the\n"
    "                         2-ring (default) or angle-weighted triangle normals\n"
    "  --no-consistency       keep the estimated tangent planes as they are (no global\n"
    "                         step making every edge meet both planes at equal angles)\n"
    "  --no-file-normals      ignore the file's NormalAtVertices\n"
    "  --handle circular|projection\n"
    "                         edge control points: arc-exact length (default) or the\n"
    "                         projection of the 1/3 point onto the tangent plane\n"
    "  --no-g1                skip the G1 corrections (plain cubic patches)\n"
    "  --weld TOL             merge input vertices closer than TOL x bounding box diagonal\n"
    "\n"
    "example: anisurf reconstruct hemi.mesh -k 4 -o hemi4.mesh\n";

int parse_int(const std::string& s, const std::string& what) {
  try {
    std::size_t used = 0;
    int v = std::stoi(s, &used);
    if (used != s.size()) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw UsageError{what + " expects an integer, got '" + s + "'"};
  }
}

// All values of a repeatable option.
std::vector<std::string> all_options(ArgParser& p, const std::string& name) {
  std::vector<std::string> out;
  for (std::string v = p.option(name); !v.empty(); v = p.option(name)) out.push_back(v);
  return out;
}

std::array<int, 2> parse_edge(const std::string& s, const std::string& what) {
  const auto dash = s.find('-');
  if (dash == std::string::npos) throw UsageError{what + " expects I-J (two 1-based vertex ids), got '" + s + "'"};
  return {parse_int(s.substr(0, dash), what) - 1, parse_int(s.substr(dash + 1), what) - 1};
}

int run_reconstruct(const std::vector<std::string>& args) {
  ArgParser p(args);
  std::string out = p.option("--output", "-o");
  const std::string ks = p.option("-k");
  const int k = ks.empty() ? 2 : parse_int(ks, "-k");
  if (k < 1 || k > 64) throw UsageError{"-k expects a split factor in [1, 64]"};
  FeatureOptions fo;
  fo.ridge_angle_deg = p.option_double("--ridge-angle", fo.ridge_angle_deg);
  fo.corner_angle_deg = p.option_double("--corner-angle", fo.corner_angle_deg);
  if (!(fo.ridge_angle_deg >= 0 && fo.ridge_angle_deg <= 180)) throw UsageError{"--ridge-angle expects degrees in [0, 180]"};
  if (!(fo.corner_angle_deg >= 0 && fo.corner_angle_deg <= 180)) throw UsageError{"--corner-angle expects degrees in [0, 180]"};
  if (p.flag("--no-ridges", "-nr")) fo.detect_ridges = false;
  for (const auto& s : all_options(p, "--add-ridge")) fo.add_ridges.push_back(parse_edge(s, "--add-ridge"));
  for (const auto& s : all_options(p, "--remove-ridge")) fo.remove_ridges.push_back(parse_edge(s, "--remove-ridge"));
  for (const auto& s : all_options(p, "--add-corner")) fo.add_corners.push_back(parse_int(s, "--add-corner") - 1);
  for (const auto& s : all_options(p, "--remove-corner")) fo.remove_corners.push_back(parse_int(s, "--remove-corner") - 1);
  NormalOptions no;
  const std::string nm = p.option("--normals");
  if (nm == "angle") no.method = NormalOptions::Method::AngleWeighted;
  else if (!nm.empty() && nm != "fit") throw UsageError{"--normals expects fit or angle, got '" + nm + "'"};
  if (p.flag("--no-file-normals")) no.use_file_normals = false;
  if (p.flag("--no-consistency")) no.mirror_iterations = 0;
  BezierOptions bo;
  const std::string hm = p.option("--handle");
  if (hm == "projection") bo.handle = BezierOptions::Handle::Projection;
  else if (!hm.empty() && hm != "circular") throw UsageError{"--handle expects circular or projection, got '" + hm + "'"};
  if (p.flag("--no-g1")) bo.g1_corrections = false;
  BuildOptions build;
  build.merge_tolerance = p.option_double("--weld", 0.0);
  if (!(build.merge_tolerance >= 0 && build.merge_tolerance < 0.1))
    throw UsageError{"--weld expects a tolerance relative to the bounding box in [0, 0.1)"};
  const auto pos = p.positionals();
  if (pos.size() != 1) throw UsageError{"expected one input mesh"};
  if (out.empty()) throw UsageError{"missing the output file (-o OUT)"};

  const auto t0 = std::chrono::steady_clock::now();
  SurfaceMesh mesh = load_mesh(pos[0], nullptr, build);
  const auto t1 = std::chrono::steady_clock::now();
  const FeatureReport fr = detect_features(mesh, fo);
  const SurfaceFrames frames = compute_frames(mesh, no);
  const BezierSurface surface(mesh, frames, bo);
  const auto t2 = std::chrono::steady_clock::now();
  const SurfaceMesh fine = sample_surface(mesh, surface, k);
  const auto t3 = std::chrono::steady_clock::now();
  save_mesh(out, fine);
  const auto t4 = std::chrono::steady_clock::now();
  auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("input:    %d vertices, %d triangles (read %.3f s)\n", mesh.n_vertices(), mesh.n_triangles(), secs(t0, t1));
  std::printf("features: %d feature edges (%d ridges detected, %d interfaces, %d boundary), %d corners\n",
              fr.feature_edges, fr.detected_ridges, fr.interface_edges, fr.boundary_edges, fr.corners);
  std::printf("normals:  %d sectors: %d fitted, %d angle-weighted, %d from the file, %d constrained by curves\n",
              frames.n_sectors(), frames.fitted, frames.angle_weighted, frames.from_file, frames.constrained);
  std::printf("surface:  built in %.3f s, sampled k=%d in %.3f s\n", secs(t1, t2), k, secs(t2, t3));
  std::printf("output:   %s: %d vertices, %d triangles (written in %.3f s)\n", out.c_str(), fine.n_vertices(),
              fine.n_triangles(), secs(t3, t4));
  return 0;
}

}  // namespace

Command reconstruct_command() {
  return {"reconstruct", "sample the smooth G1 surface over a mesh (each triangle into k^2)", kReconstructHelp,
          run_reconstruct};
}

}  // namespace anisurf::cli
