// `anisurf info` and `anisurf convert`.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/cli.h"
#include "core/error.h"
#include "io/mesh_io.h"
#include "mesh/stats.h"

namespace anisurf::cli {

namespace {

const char* kInfoHelp =
    "usage: anisurf info MESH [--sol SOL] [--weld TOL] [--json]\n"
    "\n"
    "Loads a surface mesh (.mesh .meshb .obj .off .ply .stl .gltf .glb .msh .vtu .vtp\n"
    ".vtk), builds its\n"
    "connectivity and prints: vertices, triangles, edges, components, boundary loops,\n"
    "Euler characteristic, bounding box, tagged entities (ridges, corners, required,\n"
    "references), fields, what was repaired while building, and whether every\n"
    "invariant of the mesh holds (validate).\n"
    "\n"
    "options:\n"
    "  --sol SOL   also read per-vertex fields from a .sol file\n"
    "  --weld TOL  also merge vertices closer than TOL x the bounding box diagonal\n"
    "              (default 0: identical positions only); closes CAD cracks\n"
    "  --json      print one JSON object instead of text\n"
    "\n"
    "example: anisurf info falcon.mesh --json\n";

const char* kConvertHelp =
    "usage: anisurf convert IN OUT [--sol SOL] [--weld TOL] [--ascii] [--big-endian] [--medit-version 1|2]\n"
    "                      [--msh-version 4.1|2.2] [--vtk-encoding ENC] [--zlib]\n"
    "\n"
    "Reads IN, repairs what build can repair (see `anisurf info`), writes OUT in the\n"
    "format given by its extension: .mesh .meshb .obj .ply .stl .glb .msh .vtu .vtp .vtk.\n"
    "Fields (from the input file or --sol) go into OUT.sol beside a Medit output, or\n"
    "into the .msh ($NodeData), .vtu .vtp or .vtk (point data).\n"
    "The output is written to a temporary file and renamed on success.\n"
    "\n"
    "options:\n"
    "  --sol SOL            per-vertex fields to carry over\n"
    "  --weld TOL           merge vertices closer than TOL x the bounding box diagonal\n"
    "  --ascii              PLY / STL / .msh / .vtu .vtp: write text instead of binary\n"
    "  --big-endian         PLY binary: big-endian byte order\n"
    "  --medit-version N    .mesh: 1 (single precision) or 2 (double, default)\n"
    "  --msh-version V      .msh: 4.1 (default) or 2.2\n"
    "  --vtk-encoding ENC   .vtu .vtp data arrays: appended (raw, default), binary\n"
    "                       (inline base64), appended-base64 or ascii\n"
    "  --zlib               .vtu .vtp: zlib-compress the binary data arrays\n"
    "\n"
    "example: anisurf convert bunny.off bunny.mesh\n";

const char* kind_name(FieldKind k) {
  switch (k) {
    case FieldKind::Scalar: return "scalar";
    case FieldKind::Vector: return "vector";
    case FieldKind::Tensor: return "tensor";
  }
  return "?";
}

struct Loaded {
  SurfaceMesh mesh;
  BuildReport report;
  int file_vertices = 0;
  double seconds = 0;
};

BuildOptions build_options(ArgParser& p) {
  BuildOptions o;
  o.merge_tolerance = p.option_double("--weld", 0.0);
  if (!(o.merge_tolerance >= 0 && o.merge_tolerance < 0.1))
    throw UsageError{"--weld expects a tolerance relative to the bounding box in [0, 0.1)"};
  return o;
}

Loaded load_with_fields(const std::string& path, const std::string& sol, const BuildOptions& options) {
  Loaded l;
  auto t0 = std::chrono::steady_clock::now();
  l.mesh = load_mesh(path, &l.report, options);
  l.file_vertices = l.report.input_vertices;
  if (!sol.empty()) attach_fields(l.mesh, read_sol(sol, l.file_vertices), l.report);
  l.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return l;
}

nlohmann::json info_json(const std::string& path, const Loaded& l, const MeshStats& s, const ValidationReport& v) {
  nlohmann::json j;
  j["file"] = path;
  j["vertices"] = s.vertices;
  j["file_vertices"] = l.file_vertices;
  j["unique_positions"] = l.report.unique_positions;
  j["triangles"] = s.triangles;
  j["file_triangles"] = l.report.input_triangles;
  j["edges"] = s.edges;
  j["components"] = s.components;
  j["boundary_edges"] = s.boundary_edges;
  j["boundary_loops"] = s.boundary_loops;
  j["euler_characteristic"] = s.euler_characteristic;
  j["closed"] = s.boundary_edges == 0;
  j["bbox"] = {{"min", {s.bbox.lo.x, s.bbox.lo.y, s.bbox.lo.z}}, {"max", {s.bbox.hi.x, s.bbox.hi.y, s.bbox.hi.z}},
               {"diagonal", s.bbox.diagonal()}};
  j["area"] = s.area;
  j["edge_length"] = {{"min", s.min_edge}, {"mean", s.mean_edge}, {"max", s.max_edge}};
  j["min_angle_deg"] = s.min_angle_deg;
  j["tags"] = {{"ridge_edges", s.ridge_edges},         {"required_edges", s.required_edges},
               {"listed_edges", s.listed_edges},       {"corners", s.corner_vertices},
               {"required_vertices", s.required_vertices}, {"required_triangles", s.required_triangles},
               {"non_manifold_edges_cut", s.non_manifold_edges}, {"vertex_refs", s.vertex_refs},
               {"triangle_refs", s.triangle_refs},     {"edge_refs", s.edge_refs}};
  const BuildReport& r = l.report;
  j["repaired"] = {{"merged_vertices", r.merged_vertices},
                   {"unreferenced_vertices", r.unreferenced_vertices},
                   {"degenerate_triangles", r.degenerate_triangles},
                   {"duplicate_triangles", r.duplicate_triangles},
                   {"flipped_triangles", r.flipped_triangles},
                   {"non_manifold_edges", r.non_manifold_edges},
                   {"non_manifold_vertices", r.non_manifold_vertices},
                   {"non_orientable_components", r.non_orientable_components},
                   {"dropped_edges", r.dropped_edges},
                   {"zero_area_triangles", r.zero_area_triangles}};
  nlohmann::json fields = nlohmann::json::array();
  for (const auto& f : l.mesh.fields())
    fields.push_back({{"name", f.name}, {"kind", kind_name(f.kind)}, {"components", f.ncomp}});
  j["fields"] = fields;
  j["has_normals"] = l.mesh.get_vertex_property<std::uint8_t>("has_normal").is_valid();
  j["warnings"] = r.warnings;
  j["valid"] = v.ok();
  if (!v.ok()) j["validation_errors"] = v.errors;
  j["load_seconds"] = l.seconds;
  return j;
}

void print_info_text(const std::string& path, const Loaded& l, const MeshStats& s, const ValidationReport& v) {
  auto& o = std::cout;
  o << "file          " << path << "\n";
  o << "vertices      " << s.vertices;
  if (l.file_vertices != s.vertices) o << " (file: " << l.file_vertices << ")";
  if (l.report.unique_positions != l.file_vertices)
    o << " (" << l.report.unique_positions << " unique positions among the file's " << l.file_vertices << ")";
  o << "\ntriangles     " << s.triangles;
  if (l.report.input_triangles != s.triangles) o << " (file: " << l.report.input_triangles << ")";
  o << "\nedges         " << s.edges << "\n";
  o << "components    " << s.components << "\n";
  o << "boundary      " << s.boundary_edges << " edges in " << s.boundary_loops << " loops"
    << (s.boundary_edges == 0 ? " (closed)" : " (open)") << "\n";
  o << "euler         " << s.euler_characteristic;
  if (s.boundary_edges == 0 && s.components == 1 && s.euler_characteristic % 2 == 0)
    o << " (genus " << (2 - s.euler_characteristic) / 2 << ")";
  o << "\n";
  char buf[256];
  std::snprintf(buf, sizeof buf, "bbox          [%g %g %g] - [%g %g %g], diagonal %g\n", s.bbox.lo.x, s.bbox.lo.y,
                s.bbox.lo.z, s.bbox.hi.x, s.bbox.hi.y, s.bbox.hi.z, s.bbox.diagonal());
  o << buf;
  std::snprintf(buf, sizeof buf, "edge length   min %g  mean %g  max %g;  min angle %.3g deg;  area %g\n", s.min_edge,
                s.mean_edge, s.max_edge, s.min_angle_deg, s.area);
  o << buf;
  o << "tags          ridges " << s.ridge_edges << ", corners " << s.corner_vertices << ", required v/e/t "
    << s.required_vertices << "/" << s.required_edges << "/" << s.required_triangles << ", listed edges "
    << s.listed_edges << "\n";
  o << "references    " << s.triangle_refs << " triangle, " << s.edge_refs << " edge, " << s.vertex_refs
    << " vertex (distinct non-zero)\n";
  if (!l.mesh.fields().empty()) {
    o << "fields       ";
    for (const auto& f : l.mesh.fields()) o << " " << f.name << " (" << kind_name(f.kind) << ", " << f.ncomp << ")";
    o << "\n";
  }
  auto msgs = l.report.repair_messages();
  if (msgs.empty()) {
    o << "repaired      nothing\n";
  } else {
    for (std::size_t i = 0; i < msgs.size(); ++i) o << (i ? "              " : "repaired      ") << msgs[i] << "\n";
  }
  for (const auto& w : l.report.warnings)
    if (w.find(": ") != std::string::npos && w.rfind(path, 0) != 0) o << "warning       " << w << "\n";
  o << "valid         " << (v.ok() ? "yes" : "NO") << "\n";
  if (!v.ok()) o << v.summary();
  std::snprintf(buf, sizeof buf, "load time     %.3f s\n", l.seconds);
  o << buf;
}

int run_info(const std::vector<std::string>& args) {
  ArgParser p(args);
  bool json = p.flag("--json");
  std::string sol = p.option("--sol");
  BuildOptions bo = build_options(p);
  auto pos = p.positionals();
  if (pos.size() != 1) throw UsageError{"expected exactly one MESH file"};
  Loaded l = load_with_fields(pos[0], sol, bo);
  MeshStats s = compute_stats(l.mesh);
  ValidationReport v = l.mesh.validate();
  if (json)
    std::cout << info_json(pos[0], l, s, v).dump(2) << "\n";
  else
    print_info_text(pos[0], l, s, v);
  return v.ok() ? 0 : 1;
}

int run_convert(const std::vector<std::string>& args) {
  ArgParser p(args);
  WriteOptions w;
  w.binary = !p.flag("--ascii");
  w.big_endian = p.flag("--big-endian");
  std::string mv = p.option("--medit-version");
  if (!mv.empty()) {
    if (mv != "1" && mv != "2") throw UsageError{"--medit-version must be 1 or 2"};
    w.medit_version = mv == "1" ? 1 : 2;
  }
  const std::string msh = p.option("--msh-version");
  if (!msh.empty()) {
    if (msh != "4.1" && msh != "2.2") throw UsageError{"--msh-version must be 4.1 or 2.2"};
    w.msh_version = msh == "4.1" ? 41 : 22;
  }
  const std::string enc = p.option("--vtk-encoding");
  if (!w.binary) w.vtk_encoding = VtkXmlEncoding::Ascii;
  if (enc == "appended") w.vtk_encoding = VtkXmlEncoding::Appended;
  else if (enc == "binary") w.vtk_encoding = VtkXmlEncoding::Binary;
  else if (enc == "appended-base64") w.vtk_encoding = VtkXmlEncoding::AppendedBase64;
  else if (enc == "ascii") w.vtk_encoding = VtkXmlEncoding::Ascii;
  else if (!enc.empty()) throw UsageError{"--vtk-encoding must be appended, binary, appended-base64 or ascii"};
  w.vtk_compress = p.flag("--zlib");
  if (w.vtk_compress && w.vtk_encoding == VtkXmlEncoding::Ascii)
    throw UsageError{"--zlib compresses binary data: not with --ascii or --vtk-encoding ascii"};
  std::string sol = p.option("--sol");
  BuildOptions bo = build_options(p);
  auto pos = p.positionals();
  if (pos.size() != 2) throw UsageError{"expected IN and OUT"};
  MeshFormat out_format = mesh_format_from_path(pos[1]);  // fail early on a bad extension
  Loaded l = load_with_fields(pos[0], sol, bo);
  ValidationReport v = l.mesh.validate();
  if (!v.ok()) throw TopologyError(pos[0] + ": the built mesh is invalid:\n" + v.summary());
  save_mesh(pos[1], l.mesh, w);
  std::string written = pos[1];
  if (!l.mesh.fields().empty() && (out_format == MeshFormat::Medit || out_format == MeshFormat::MeditBinary)) {
    std::filesystem::path solp(pos[1]);
    solp.replace_extension(out_format == MeshFormat::Medit ? ".sol" : ".solb");
    write_sol(solp.string(), extract_fields(l.mesh), l.mesh.n_vertices(), l.mesh.dimension());
    written += " and " + solp.string();
  }
  for (const auto& m : l.report.repair_messages()) std::cerr << "repaired: " << m << "\n";
  std::cout << "wrote " << written << ": " << l.mesh.n_vertices() << " vertices, " << l.mesh.n_triangles()
            << " triangles\n";
  return 0;
}

}  // namespace

Command info_command() { return {"info", "print counts, topology, tags and repairs of a mesh", kInfoHelp, run_info}; }
Command convert_command() { return {"convert", "convert a mesh between formats", kConvertHelp, run_convert}; }

}  // namespace anisurf::cli
