// The commands that need OpenGL: `shot` (headless PNG through OSMesa) and
// `view` (the GLFW window). app/main.cpp adds them when built with GL.
#pragma once
#include <vector>

#include "cli/cli.h"

namespace anisurf {

std::vector<cli::Command> gl_commands();

}  // namespace anisurf
