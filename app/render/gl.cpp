#include "render/gl.h"

namespace anisurf::gl {

#define ANISURF_GL_DEFINE(type, name) type name = nullptr;
ANISURF_GL_FUNCTIONS(ANISURF_GL_DEFINE)
#undef ANISURF_GL_DEFINE

namespace {
bool g_loaded = false;
}

std::vector<std::string> load_gl(GetProcAddress get) {
  std::vector<std::string> missing;
#define ANISURF_GL_LOAD(type, name)                        \
  name = reinterpret_cast<type>(get(#name));               \
  if (!name) missing.emplace_back(#name);
  ANISURF_GL_FUNCTIONS(ANISURF_GL_LOAD)
#undef ANISURF_GL_LOAD
  g_loaded = missing.empty();
  return missing;
}

bool gl_loaded() { return g_loaded; }

std::string gl_description() {
  if (!g_loaded) return "OpenGL not loaded";
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return "OpenGL " + str(GL_VERSION) + ", " + str(GL_RENDERER);
}

}  // namespace anisurf::gl
