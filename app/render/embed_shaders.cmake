# Writes OUTPUT: a C++ source holding every shader of SHADER_DIR (*.vert,
# *.frag) as a string, looked up by file name through render/shaders.h.
file(GLOB files RELATIVE ${SHADER_DIR} ${SHADER_DIR}/*.vert ${SHADER_DIR}/*.frag)
list(SORT files)
set(body "")
foreach(f ${files})
  file(READ ${SHADER_DIR}/${f} text)
  string(FIND "${text}" ")glsl\"" bad)
  if(NOT bad EQUAL -1)
    message(FATAL_ERROR "${f} contains the raw string delimiter )glsl\"")
  endif()
  string(APPEND body "    {\"${f}\", R\"glsl(${text})glsl\"},\n")
endforeach()
set(content "// Generated from ${SHADER_DIR} by embed_shaders.cmake: do not edit.
#include \"render/shaders.h\"

#include <array>
#include <utility>

namespace anisurf::render {
namespace {
const std::pair<std::string_view, std::string_view> kShaders[] = {
${body}};
}  // namespace

std::string_view shader_source(std::string_view name) {
  for (const auto& [n, s] : kShaders)
    if (n == name) return s;
  return {};
}

std::vector<std::string_view> shader_names() {
  std::vector<std::string_view> out;
  for (const auto& [n, s] : kShaders) out.push_back(n);
  return out;
}

}  // namespace anisurf::render
")
# Only touch the output when it changes (no needless rebuilds).
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
  if(old STREQUAL content)
    return()
  endif()
endif()
file(WRITE ${OUTPUT} "${content}")
