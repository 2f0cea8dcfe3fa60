// anisurf: anisotropic surface mesh adaptation (the program's entry point).
#include "cli/cli.h"
#include "large_blocks.h"
#ifdef __GLIBC__
#include <malloc.h>
#endif
#ifdef ANISURF_WITH_GL
#include "editor/editor_app.h"
#include "render/gl_commands.h"
#endif

int main(int argc, char** argv) {
#ifdef __GLIBC__
  // Arrays of 256 KB and more are mapped on their own and given back to the
  // system when freed. glibc's default raises that threshold after the first
  // large free (up to 32 MB), after which the buffers a growing mesh leaves
  // behind stay resident in the heap: ~10% more peak memory on the large
  // refinements (bench/bench_remesh.py). large_blocks.cpp makes their
  // pages resident in one call, or backs them with huge pages.
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(anisurf::app::kMappedBlock));
  // Smaller blocks come from the heap, whose free top glibc gives back to
  // the system beyond 128 KB: the next pass then faults the same pages in
  // again, one by one (slow on virtual machines: 20% of a 0.4 s run's time).
  // The top is kept up to 64 MB; the peak stays within a few MB
  // (bench/bench_remesh.py --peer).
  mallopt(M_TRIM_THRESHOLD, 64 * 1024 * 1024);
#endif
  auto commands = anisurf::cli::engine_commands();
#ifdef ANISURF_WITH_GL
  for (auto& c : anisurf::gl_commands()) commands.push_back(std::move(c));
  // No subcommand, a mesh file or --script: the editor.
  std::vector<std::string> names;
  for (const auto& c : commands) names.push_back(c.name);
  if (auto code = anisurf::editor::editor_main(std::vector<std::string>(argv + 1, argv + argc), names)) return *code;
#endif
  return anisurf::cli::run(argc, argv, commands);
}
