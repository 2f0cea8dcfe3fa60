// Times the smooth surface: feature detection, tangent planes, the Bezier
// surface build, and evaluations per second (position only, and position +
// derivatives + normal) at random points of random triangles.
// Usage: bench_geometry [MESH ...]
//   (default: ../shared/bench/inputs/hemi.mesh and sphere20k.mesh)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "geometry/bezier_surface.h"
#include "geometry/features.h"
#include "geometry/normals.h"
#include "io/mesh_io.h"

using namespace anisurf;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files(argv + 1, argv + argc);
  if (files.empty()) files = {"../shared/bench/inputs/hemi.mesh", "../shared/bench/inputs/sphere20k.mesh"};
  std::printf("%-36s %9s %9s %9s %9s %12s %12s\n", "file", "triangles", "feat s", "frames s", "build s",
              "Mpos/s", "Meval/s");
  for (const auto& f : files) {
    try {
      SurfaceMesh mesh = load_mesh(f);
      double t_feat = 1e30, t_frames = 1e30, t_build = 1e30;
      BezierSurface surface;
      for (int rep = 0; rep < 3; ++rep) {
        SurfaceMesh m = mesh;
        auto t0 = std::chrono::steady_clock::now();
        detect_features(m);
        t_feat = std::min(t_feat, seconds_since(t0));
        t0 = std::chrono::steady_clock::now();
        const SurfaceFrames frames = compute_frames(m);
        t_frames = std::min(t_frames, seconds_since(t0));
        t0 = std::chrono::steady_clock::now();
        surface = BezierSurface(m, frames);
        t_build = std::min(t_build, seconds_since(t0));
      }
      // random query points
      const int n = 2'000'000;
      std::mt19937 rng(1);
      std::uniform_int_distribution<int> tri(0, mesh.n_triangles() - 1);
      std::uniform_real_distribution<double> u(0, 1);
      std::vector<Triangle> ts(n);
      std::vector<Bary> bs(n);
      for (int i = 0; i < n; ++i) {
        double x = u(rng), y = u(rng);
        if (x + y > 1) x = 1 - x, y = 1 - y;
        ts[i] = Triangle(tri(rng));
        bs[i] = {1 - x - y, x, y};
      }
      double best_pos = 1e30, best_eval = 1e30;
      Vec3 sink;
      for (int rep = 0; rep < 3; ++rep) {
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) sink += surface.position(ts[i], bs[i]);
        best_pos = std::min(best_pos, seconds_since(t0));
        t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) sink += surface.evaluate(ts[i], bs[i]).normal;
        best_eval = std::min(best_eval, seconds_since(t0));
      }
      std::printf("%-36s %9d %9.4f %9.4f %9.4f %12.2f %12.2f%s\n", f.c_str(), mesh.n_triangles(), t_feat, t_frames,
                  t_build, n / best_pos / 1e6, n / best_eval / 1e6, norm(sink) == -1 ? "!" : "");
    } catch (const Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  return 0;
}
