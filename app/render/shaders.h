// GLSL sources of <repo>/shaders, embedded into the binary at build time
// (embed_shaders.cmake), so that a relocated binary needs no data directory.
#pragma once
#include <string_view>
#include <vector>

namespace anisurf::render {

// Source of a shader file ("surface.frag"), or an empty view if unknown.
std::string_view shader_source(std::string_view name);
// Every embedded file name (sorted).
std::vector<std::string_view> shader_names();

}  // namespace anisurf::render
