// Loading the OpenGL functions of render/gl.h, declared without any GL
// header so that the OSMesa backend (whose <GL/osmesa.h> pulls <GL/gl.h>)
// can call it.
#pragma once
#include <string>
#include <vector>

namespace anisurf::gl {

using ProcAddress = void (*)();
using GetProcAddress = ProcAddress (*)(const char* name);

// Fills every function pointer of render/gl.h from `get` (the current
// context's loader). Returns the names that could not be resolved (empty on
// success). The pointers are process-wide: one loaded set serves every
// context of the same driver.
std::vector<std::string> load_gl(GetProcAddress get);

// True once load_gl() succeeded.
bool gl_loaded();

// "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)"
std::string gl_description();

}  // namespace anisurf::gl
