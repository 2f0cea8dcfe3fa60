#include "render/gl_commands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "core/error.h"
#include "editor/editor_app.h"
#include "editor/script.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "io/mesh_io.h"
#include "render/bezier_structure.h"
#include "render/headless.h"
#include "render/mesh_structure.h"
#include "render/viewer.h"

namespace anisurf {

namespace {

using cli::ArgParser;
using cli::UsageError;
using Clock = std::chrono::steady_clock;
namespace r = render;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

const char* kDisplayOptions =
    "  --sol SOL              per-vertex fields (metric tensor or size map, scalar fields)\n"
    "  --color MODE           colour the surface by: quality (eq. 17, in the metric if any),\n"
    "                         length (metric edge length: blue short, grey 1, red long),\n"
    "                         size | aniso (of the metric in the tangent plane),\n"
    "                         field NAME (a scalar / vector field of the .sol), ref\n"
    "                         (triangle references), none (default)\n"
    "  --colormap NAME        viridis | coolwarm (default: per quantity)\n"
    "  --range MIN:MAX        values at the ends of the colormap (default: per quantity)\n"
    "  --glyphs               draw the metric's unit ellipses in the tangent planes\n"
    "  --glyph-density F      fraction of the vertices with a glyph (default: about 2500 glyphs)\n"
    "  --glyph-scale S        glyph size relative to the unit ellipse (default: the drawn\n"
    "                         glyphs nearly touch; the legend shows the scale)\n"
    "  --wire                 wireframe overlay\n"
    "  --flat                 flat shading (default: smooth, split at ridges and creases)\n"
    "  --crease DEG           display crease angle for smooth shading (default 50; 180: none)\n"
    "  --no-features          hide ridges, boundaries, corners\n"
    "  --no-legend            hide the legend\n"
    "  --highlight-tri IDS    highlight triangles, e.g. 12,40-45 (numbered from 1)\n"
    "  --highlight-vert IDS   mark vertices (numbered from 1)\n"
    "  --view NAME            iso|front|back|top|bottom|left|right (default iso; front for 2D)\n"
    "  --yaw DEG, --pitch DEG camera angles about the up axis and above the horizon,\n"
    "                         replacing the view's (front: 0, 0; iso: 45, 35.3)\n"
    "  --up y|z               the world's up axis (default y)\n"
    "  --ortho                orthographic projection (default perspective)\n"
    "  --zoom F               zoom in by F after fitting the view (default 1)\n"
    "  --background COLOR     white (default), black, or RRGGBB\n"
    "  --msaa N               multisampling samples, 1 to disable (default 4)\n"
    "  --bezier K             draw the G1 Bezier surface (report section 3) instead of the\n"
    "                         mesh, each triangle sampled K x K, with the mesh edges on it;\n"
    "                         --color deviation colours it by the distance to the mesh\n"
    "  --control-net          with --bezier: the control net (31 points per triangle)\n";

struct DisplayArgs {
  std::string sol;
  std::string color;  // "", quality, length, size, aniso, field:NAME, ref, none
  std::optional<r::Colormap> colormap;
  std::optional<std::pair<float, float>> range;
  bool glyphs = false, wire = false, flat = false, ortho = false;
  bool features = true, legend = true;
  float glyph_density = 0, glyph_scale = 0;
  double crease = 50;
  std::vector<int> highlight_tri, highlight_vert;
  std::optional<r::NamedView> view;
  r::UpAxis up = r::UpAxis::Y;
  float zoom = 1;
  std::optional<float> yaw, pitch;  // degrees, override the view's angles
  glm::vec3 background{1, 1, 1};
  int msaa = 4;
  int bezier = 0;  // > 0: samples per edge of the G1 surface
  bool control_net = false;
};

// "--color field NAME" -> "--color field:NAME" (ArgParser options take one value).
std::vector<std::string> merge_color_field(std::vector<std::string> args) {
  for (std::size_t i = 0; i + 2 < args.size(); ++i)
    if (args[i] == "--color" && args[i + 1] == "field" && args[i + 2].rfind("-", 0) != 0) {
      args[i + 1] = "field:" + args[i + 2];
      args.erase(args.begin() + static_cast<std::ptrdiff_t>(i) + 2);
    }
  return args;
}

std::vector<int> parse_ids(const std::string& option, const std::string& text) {
  std::vector<int> ids;
  std::size_t pos = 0;
  auto bad = [&]() -> UsageError {
    return UsageError{option + " expects ids numbered from 1 like 12,40-45, got '" + text + "'"};
  };
  while (pos < text.size()) {
    std::size_t end = text.find(',', pos);
    std::string item = text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? text.size() : end + 1;
    std::size_t dash = item.find('-', 1);
    try {
      std::size_t used = 0;
      long a = std::stol(item.substr(0, dash), &used);
      if (used != item.substr(0, dash).size()) throw bad();
      long b = a;
      if (dash != std::string::npos) {
        b = std::stol(item.substr(dash + 1), &used);
        if (used != item.size() - dash - 1) throw bad();
      }
      if (a < 1 || b < a || b - a > 10'000'000) throw bad();
      for (long i = a; i <= b; ++i) ids.push_back(static_cast<int>(i - 1));
    } catch (const UsageError&) {
      throw;
    } catch (const std::exception&) {
      throw bad();
    }
  }
  if (ids.empty()) throw bad();
  return ids;
}

std::pair<int, int> parse_size(const std::string& text) {
  auto bad = [&] {
    return UsageError{"--size expects WIDTHxHEIGHT between 16 and 8192, e.g. 1600x1000, got '" + text + "'"};
  };
  std::size_t x = text.find('x');
  if (x == std::string::npos) throw bad();
  try {
    std::size_t u1 = 0, u2 = 0;
    int w = std::stoi(text.substr(0, x), &u1), h = std::stoi(text.substr(x + 1), &u2);
    if (u1 != x || u2 != text.size() - x - 1 || w < 16 || h < 16 || w > 8192 || h > 8192) throw bad();
    return {w, h};
  } catch (const UsageError&) {
    throw;
  } catch (const std::exception&) {
    throw bad();
  }
}

glm::vec3 parse_color(const std::string& text) {
  if (text == "white") return {1, 1, 1};
  if (text == "black") return {0, 0, 0};
  std::string h = !text.empty() && text[0] == '#' ? text.substr(1) : text;
  if (h.size() == 6 && h.find_first_not_of("0123456789abcdefABCDEF") == std::string::npos) {
    unsigned v = static_cast<unsigned>(std::stoul(h, nullptr, 16));
    return glm::vec3((v >> 16) & 0xff, (v >> 8) & 0xff, v & 0xff) / 255.0f;
  }
  throw UsageError{"--background expects white, black or RRGGBB, got '" + text + "'"};
}

DisplayArgs parse_display(ArgParser& p) {
  DisplayArgs a;
  a.sol = p.option("--sol");
  a.color = p.option("--color");
  const std::vector<std::string> modes = {"quality", "length", "size", "aniso", "ref", "none", "deviation"};
  if (!a.color.empty() && a.color.rfind("field:", 0) != 0 &&
      std::find(modes.begin(), modes.end(), a.color) == modes.end()) {
    if (a.color == "field") throw UsageError{"--color field needs the field's name: --color field NAME"};
    throw UsageError{"--color expects quality|length|size|aniso|field NAME|ref|none, got '" + a.color + "'"};
  }
  if (std::string cm = p.option("--colormap"); !cm.empty()) {
    a.colormap = r::parse_colormap(cm);
    if (!a.colormap) throw UsageError{"--colormap expects viridis or coolwarm, got '" + cm + "'"};
  }
  if (std::string rg = p.option("--range"); !rg.empty()) {
    std::size_t c = rg.find(':');
    try {
      if (c == std::string::npos) throw std::invalid_argument(rg);
      float lo = std::stof(rg.substr(0, c)), hi = std::stof(rg.substr(c + 1));
      if (!(hi > lo)) throw std::invalid_argument(rg);
      a.range = std::make_pair(lo, hi);
    } catch (const std::exception&) {
      throw UsageError{"--range expects MIN:MAX with MIN < MAX, got '" + rg + "'"};
    }
  }
  a.glyphs = p.flag("--glyphs");
  a.wire = p.flag("--wire");
  a.flat = p.flag("--flat");
  a.ortho = p.flag("--ortho");
  a.features = !p.flag("--no-features");
  a.legend = !p.flag("--no-legend");
  a.glyph_density = static_cast<float>(p.option_double("--glyph-density", 0));
  if (a.glyph_density < 0 || a.glyph_density > 1)
    throw UsageError{"--glyph-density expects a fraction in (0, 1]"};
  a.glyph_scale = static_cast<float>(p.option_double("--glyph-scale", 0));
  if (a.glyph_scale < 0) throw UsageError{"--glyph-scale expects a positive number"};
  a.crease = p.option_double("--crease", 50);
  if (a.crease < 0 || a.crease > 180) throw UsageError{"--crease expects an angle in degrees in [0, 180]"};
  if (std::string ids = p.option("--highlight-tri"); !ids.empty()) a.highlight_tri = parse_ids("--highlight-tri", ids);
  if (std::string ids = p.option("--highlight-vert"); !ids.empty())
    a.highlight_vert = parse_ids("--highlight-vert", ids);
  if (std::string v = p.option("--view"); !v.empty()) {
    a.view = r::parse_view(v);
    if (!a.view) throw UsageError{"--view expects " + r::view_names() + ", got '" + v + "'"};
  }
  if (std::string up = p.option("--up"); !up.empty()) {
    if (up != "y" && up != "z") throw UsageError{"--up expects y or z, got '" + up + "'"};
    a.up = up == "y" ? r::UpAxis::Y : r::UpAxis::Z;
  }
  if (std::string y = p.option("--yaw"); !y.empty()) a.yaw = static_cast<float>(ArgParser({"--yaw", y}).option_double("--yaw", 0));
  if (std::string y = p.option("--pitch"); !y.empty()) {
    a.pitch = static_cast<float>(ArgParser({"--pitch", y}).option_double("--pitch", 0));
    if (std::abs(*a.pitch) > 90) throw UsageError{"--pitch expects degrees in [-90, 90]"};
  }
  a.zoom = static_cast<float>(p.option_double("--zoom", 1));
  if (!(a.zoom > 0)) throw UsageError{"--zoom expects a positive factor"};
  if (std::string bg = p.option("--background"); !bg.empty()) a.background = parse_color(bg);
  double msaa = p.option_double("--msaa", 4);
  if (msaa != 1 && msaa != 2 && msaa != 4 && msaa != 8) throw UsageError{"--msaa expects 1, 2, 4 or 8"};
  a.msaa = static_cast<int>(msaa);
  if (std::string k = p.option("--bezier"); !k.empty()) {
    double kv = ArgParser({"--bezier", k}).option_double("--bezier", 0);
    if (kv != std::floor(kv) || kv < 1 || kv > 32) throw UsageError{"--bezier expects a sampling K in [1, 32], got '" + k + "'"};
    a.bezier = static_cast<int>(kv);
  }
  a.control_net = p.flag("--control-net");
  if (a.control_net && a.bezier == 0) throw UsageError{"--control-net needs --bezier K"};
  if (a.color == "deviation" && a.bezier == 0) throw UsageError{"--color deviation needs --bezier K"};
  if (a.bezier > 0 && !a.color.empty() && a.color != "deviation" && a.color != "none")
    throw UsageError{"with --bezier, --color takes deviation or none"};
  return a;
}

struct LoadedScene {
  r::Scene scene;
  r::UiState ui;
  double load_seconds = 0, build_seconds = 0;
};

std::string no_metric_reason(const r::MeshStructure& ms) {
  return ms.metric_problem.empty() ? "give --sol with a metric tensor field (or a size field)" : ms.metric_problem;
}

std::string quantity_for(const DisplayArgs& a, const r::MeshStructure& ms, const SurfaceMesh& mesh) {
  const std::string& c = a.color;
  auto need_metric = [&](const char* what) {
    if (ms.metric_field.empty()) throw Error(std::string("--color ") + what + " needs a metric: " + no_metric_reason(ms));
  };
  if (c.empty() || c == "none" || c == "deviation") return "";
  if (c == "quality") return r::quantity::kQuality;
  if (c == "length") return r::quantity::kLength;
  if (c == "size") return need_metric("size"), r::quantity::kSize;
  if (c == "aniso") return need_metric("aniso"), r::quantity::kAniso;
  if (c == "ref") return r::quantity::kReference;
  std::string name = c.substr(6);  // field:NAME
  for (const auto& q : ms.structure.scalars)
    if (q.name == name || q.name == "field " + name) return q.name;
  std::string names;
  for (const auto& f : mesh.fields())
    if (f.kind != FieldKind::Tensor) names += (names.empty() ? "" : ", ") + f.name;
  throw Error("--color field: no scalar or vector field named '" + name + "' (fields: " +
              (names.empty() ? std::string(a.sol.empty() ? "none; give --sol" : "none") : names) + ")");
}

LoadedScene load_scene(const std::string& mesh_path, const DisplayArgs& a, float aspect) {
  LoadedScene out;
  auto t0 = Clock::now();
  BuildReport report;
  SurfaceMesh mesh = load_mesh(mesh_path, &report);
  if (!a.sol.empty()) attach_fields(mesh, read_sol(a.sol, report.input_vertices), report);
  out.load_seconds = seconds_since(t0);

  t0 = Clock::now();
  r::MeshStructureOptions mo;
  mo.crease_angle_deg = a.crease;
  mo.glyph_density = a.glyph_density;
  mo.glyph_scale = a.glyph_scale;
  mo.vertex_origin = report.vertex_origin;
  r::MeshStructure ms = r::make_mesh_structure(mesh, std::filesystem::path(mesh_path).filename().string(), mo);
  if (a.glyphs && ms.metric_field.empty()) throw Error("--glyphs needs a metric: " + no_metric_reason(ms));
  if (!ms.metric_problem.empty() && (a.color == "quality" || a.color == "length"))
    std::cerr << "warning: " << ms.metric_problem << "; drawing Euclidean " << a.color << "\n";
  std::string active = quantity_for(a, ms, mesh);
  if (!a.highlight_tri.empty() || !a.highlight_vert.empty()) r::highlight(ms, a.highlight_tri, a.highlight_vert);
  r::SurfaceStructure& s = ms.structure;
  s.activate(active);
  for (auto& q : s.scalars)
    if (q.name == active) {
      if (a.colormap) q.colormap = *a.colormap;
      if (a.range) {
        q.range_min = a.range->first;
        q.range_max = a.range->second;
        if (q.log_scale && q.range_min <= 0)
          throw Error("--range: " + q.name + " is drawn on a log scale: MIN must be > 0");
      }
    }
  for (auto& g : s.glyphs) g.enabled = a.glyphs;
  for (auto& c : s.curves) c.enabled = a.features;
  for (auto& m : s.markers) m.enabled = a.features || m.name == "highlighted vertices";

  r::Scene& scene = out.scene;
  scene.display.flat = a.flat;
  scene.display.wireframe = a.wire;
  scene.display.legend = a.legend;
  scene.display.background = a.background;
  scene.display.msaa_samples = a.msaa;
  scene.camera.up_axis = a.up;
  scene.camera.orthographic = a.ortho;
  scene.camera.set_view(a.view ? *a.view : (mesh.dimension() == 2 ? r::NamedView::Front : r::NamedView::Iso));
  if (a.yaw) scene.camera.yaw = glm::radians(*a.yaw);
  if (a.pitch) scene.camera.pitch = glm::radians(*a.pitch);
  out.ui.title = s.name;
  out.ui.info = std::to_string(s.geometry.positions.size()) + " vertices, " +
                std::to_string(s.geometry.triangles.size()) + " triangles" +
                (ms.metric_field.empty() ? "" : ", metric '" + ms.metric_field + "'");
  if (a.bezier > 0) {
    // The G1 surface over the mesh with its features (detected on a copy so
    // the mesh's own display keeps the file's tags).
    SurfaceMesh tagged = mesh;
    detect_features(tagged);
    const BezierSurface surface(tagged, compute_frames(tagged));
    r::BezierStructureOptions bo;
    bo.k = a.bezier;
    bo.control_net = a.control_net;
    r::SurfaceStructure b = r::make_bezier_structure(tagged, surface, "G1 surface", bo);
    if (a.color == "deviation") b.activate(r::quantity::kDeviation);
    for (auto& q : b.scalars) {
      if (a.colormap) q.colormap = *a.colormap;
      if (a.range) q.range_min = a.range->first, q.range_max = a.range->second;
    }
    s.enabled = false;  // the surface replaces the mesh (its edges are drawn on it)
    scene.surfaces.push_back(std::move(b));
    out.ui.info += "; G1 surface sampled " + std::to_string(a.bezier) + "x" + std::to_string(a.bezier);
  }
  scene.surfaces.push_back(std::move(s));
  scene.fit_camera(aspect);
  scene.camera.zoom(1.0f / a.zoom);
  out.build_seconds = seconds_since(t0);
  return out;
}

// --- shot ---------------------------------------------------------------------

int run_shot(const std::vector<std::string>& raw) {
  ArgParser p(merge_color_field(raw));
  std::string out = p.option("-o", "--output");
  std::string size = p.option("--size");
  auto [width, height] = parse_size(size.empty() ? "1600x1000" : size);
  bool ui_panel = p.flag("--ui");
  bool verbose = p.flag("--verbose");
  DisplayArgs a = parse_display(p);
  std::vector<std::string> pos = p.positionals();
  if (pos.size() != 1) throw UsageError{pos.empty() ? "missing MESH" : "one MESH expected, got " + std::to_string(pos.size()) + " arguments"};
  if (out.empty()) throw UsageError{"missing -o OUT.png"};
  std::string ext = std::filesystem::path(out).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png") throw UsageError{"-o: the output must be a .png file, got '" + out + "'"};

  auto t0 = Clock::now();
  LoadedScene ls = load_scene(pos[0], a, static_cast<float>(width) / static_cast<float>(height));
  ls.ui.show_panel = ui_panel;
  auto t1 = Clock::now();
  r::HeadlessRenderer renderer(width, height);
  double context_s = seconds_since(t1);
  t1 = Clock::now();
  // Keep the strips of the legend and the panel free: measure them, then fit
  // the camera again.
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  renderer.layout_ui(ls.scene, ls.ui, width, height);
  if (ls.ui.legend_width > 0 || ls.ui.panel_width > 0) {
    ls.scene.fit_camera(aspect, ls.ui.left_reserve(width), ls.ui.right_reserve(width));
    ls.scene.camera.zoom(1.0f / a.zoom);
  }
  r::Image img = renderer.render(ls.scene, ls.ui, width, height);
  double render_s = seconds_since(t1);
  t1 = Clock::now();
  r::write_png(out, img);
  double png_s = seconds_since(t1);
  std::cout << "wrote " << out << " (" << width << "x" << height << ")\n";
  if (verbose)
    std::fprintf(stderr,
                 "shot: load %.3f s, structure %.3f s, context %.3f s, render %.3f s, png %.3f s, total %.3f s\n"
                 "shot: %s\n",
                 ls.load_seconds, ls.build_seconds, context_s, render_s, png_s, seconds_since(t0),
                 renderer.description().c_str());
  return 0;
}

// --- view ---------------------------------------------------------------------

int run_view(const std::vector<std::string>& raw) {
  ArgParser p(merge_color_field(raw));
  std::string size = p.option("--size");
  auto [width, height] = parse_size(size.empty() ? "1280x800" : size);
  int bench = static_cast<int>(p.option_double("--bench-orbit", 0));
  if (bench < 0) throw UsageError{"--bench-orbit expects a number of frames"};
  double max_fps = p.option_double("--max-fps", 60);
  if (!(max_fps >= 1)) throw UsageError{"--max-fps expects a frame rate >= 1"};
  const bool bench_full_detail = p.flag("--bench-full-detail");
  if (bench_full_detail && bench == 0) throw UsageError{"--bench-full-detail goes with --bench-orbit N"};
  DisplayArgs a = parse_display(p);
  std::vector<std::string> pos = p.positionals();
  if (pos.empty() || pos.size() > 2) throw UsageError{pos.empty() ? "missing MESH" : "expected MESH [SOL]"};
  if (pos.size() == 2) {
    if (!a.sol.empty()) throw UsageError{"give the .sol either as the second argument or with --sol, not both"};
    a.sol = pos[1];
  }
  LoadedScene ls = load_scene(pos[0], a, static_cast<float>(width) / static_cast<float>(height));
  r::ViewerOptions vo;
  vo.width = width;
  vo.height = height;
  vo.title = "anisurf - " + ls.ui.title;
  vo.max_fps = max_fps;
  vo.bench_orbit_frames = bench;
  vo.bench_full_detail = bench_full_detail;
  r::run_viewer(ls.scene, ls.ui, vo);
  return 0;
}

}  // namespace

std::vector<cli::Command> gl_commands() {
  std::vector<cli::Command> list;
  list.push_back(
      {"shot", "render a mesh to a PNG without a display (OSMesa)",
       std::string("usage: anisurf shot MESH [options] -o OUT.png\n\n"
                   "Renders MESH headless (software OpenGL through OSMesa: no display, no GPU) and\n"
                   "writes a PNG. The same command gives the same bytes. Feature edges (ridges,\n"
                   "boundaries, non-manifold cuts) and corners are drawn unless --no-features.\n\n"
                   "options:\n"
                   "  -o, --output OUT.png   the picture (written through a temporary file)\n"
                   "  --size WxH             picture size in pixels (default 1600x1000)\n"
                   "  --ui                   also draw the control panel (as in `anisurf view`)\n"
                   "  --verbose              print timings and the OpenGL renderer on stderr\n") +
           kDisplayOptions +
           "\nexample:\n"
           "  anisurf shot fandisk.off --wire --view iso -o fandisk.png\n"
           "  anisurf shot falcon.mesh --sol falcon.sol --color length --glyphs -o falcon.png\n",
       run_shot});
  list.push_back({"view", "open a mesh in an interactive window",
                  std::string("usage: anisurf view MESH [SOL] [options]\n\n"
                              "Opens a window (needs a display; on a headless machine run it under\n"
                              "xvfb-run -a -s \"-screen 0 1280x800x24\"). The panel switches colours,\n"
                              "features, glyphs, shading and views.\n\n") +
                      render::viewer_keys() +
                      "\noptions:\n"
                      "  --size WxH             window size (default 1280x800)\n"
                      "  --max-fps F            frame cap (default 60)\n"
                      "  --bench-orbit N        orbit 360 degrees in N frames as fast as possible,\n"
                      "                         print the frame rate and exit (drawn as while the\n"
                      "                         camera moves: half resolution, proxies of meshes\n"
                      "                         over 400k triangles; the line says what was drawn)\n"
                      "  --bench-full-detail    the orbit's frames drawn as still ones instead\n" +
                      kDisplayOptions +
                      "\nexample:\n"
                      "  anisurf view falcon.mesh falcon.sol --color aniso --glyphs\n",
                  run_view});
  list.push_back({"editor", "the editor window or a script (also: anisurf [MESH [SOL]], anisurf --script FILE)",
                  std::string(editor::editor_help()) + "\n" + editor::script_help(),
                  [](const std::vector<std::string>& args) {
                    std::vector<std::string> names;  // after `editor` every word is the editor's
                    if (auto code = editor::editor_main(args, names)) return *code;
                    throw UsageError{"expected [MESH [SOL]] with an existing MESH, or --script FILE"};
                  }});
  return list;
}

}  // namespace anisurf
