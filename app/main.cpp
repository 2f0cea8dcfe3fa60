// anisurf: anisotropic surface mesh adaptation (the program's entry point).
#include "cli/cli.h"
#ifdef ANISURF_WITH_GL
#include "editor/editor_app.h"
#include "render/gl_commands.h"
#endif

int main(int argc, char** argv) {
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
