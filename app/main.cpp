// anisurf: anisotropic surface mesh adaptation (the program's entry point).
#include "cli/cli.h"
#ifdef ANISURF_WITH_GL
#include "render/gl_commands.h"
#endif

int main(int argc, char** argv) {
  auto commands = anisurf::cli::engine_commands();
#ifdef ANISURF_WITH_GL
  for (auto& c : anisurf::gl_commands()) commands.push_back(std::move(c));
#endif
  return anisurf::cli::run(argc, argv, commands);
}
