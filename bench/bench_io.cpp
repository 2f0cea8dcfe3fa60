// Prints the time to read a mesh file and to build its corner table.
// Usage: bench_io [MESH ...]   (default: ../shared/meshes/falcon.mesh)
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/mesh_io.h"

using namespace anisurf;

int main(int argc, char** argv) {
  std::vector<std::string> files(argv + 1, argv + argc);
  if (files.empty()) files.push_back("../shared/meshes/falcon.mesh");
  std::printf("%-40s %10s %10s %10s %10s\n", "file", "triangles", "read s", "build s", "Mtri/s");
  for (const auto& f : files) {
    try {
      double best_read = 1e30, best_build = 1e30;
      int nt = 0;
      for (int rep = 0; rep < 5; ++rep) {
        auto t0 = std::chrono::steady_clock::now();
        MeshData d = read_mesh_data(f);
        auto t1 = std::chrono::steady_clock::now();
        SurfaceMesh m;
        build_mesh(d, m);
        auto t2 = std::chrono::steady_clock::now();
        best_read = std::min(best_read, std::chrono::duration<double>(t1 - t0).count());
        best_build = std::min(best_build, std::chrono::duration<double>(t2 - t1).count());
        nt = m.n_triangles();
      }
      std::printf("%-40s %10d %10.4f %10.4f %10.2f\n", f.c_str(), nt, best_read, best_build,
                  nt / (best_read + best_build) / 1e6);
    } catch (const Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  return 0;
}
