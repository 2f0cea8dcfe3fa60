// Force-included (-include) into Dear ImGui's imgui_impl_opengl3.cpp, which is
// compiled with IMGUI_IMPL_OPENGL_LOADER_CUSTOM: its unqualified gl* calls then
// resolve to our runtime-loaded pointers (render/gl.h), and the GL_VERSION_3_x
// macros of glcorearb.h enable its desktop GL 3.3 paths.
#pragma once
#include "render/gl.h"

using namespace anisurf::gl;  // NOLINT: the backend calls gl* unqualified
