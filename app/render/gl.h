// OpenGL 3.3 core functions, loaded at run time.
//
// Every GL call of the renderer (and of Dear ImGui's OpenGL3 backend, see
// imgui_gl_loader.h) goes through the function pointers declared here, filled
// by load_gl() from the current context's GetProcAddress: glfwGetProcAddress
// for the window, OSMesaGetProcAddress for headless shots. Nothing links
// libGL, so the two backends can live in one binary.
//
// The pointers are C++ variables in namespace anisurf::gl, named like the GL
// functions; code that calls GL says `using namespace anisurf::gl;`. A source
// file must not include both this header and <GL/gl.h> (osmesa.h includes it).
#pragma once
#include <GL/glcorearb.h>

#include "render/gl_load.h"

// X(pointer type, name) for each function used.
#define ANISURF_GL_FUNCTIONS(X) \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture) \
  X(PFNGLATTACHSHADERPROC, glAttachShader) \
  X(PFNGLBINDBUFFERPROC, glBindBuffer) \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer) \
  X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer) \
  X(PFNGLBINDSAMPLERPROC, glBindSampler) \
  X(PFNGLBINDTEXTUREPROC, glBindTexture) \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray) \
  X(PFNGLBLENDEQUATIONPROC, glBlendEquation) \
  X(PFNGLBLENDEQUATIONSEPARATEPROC, glBlendEquationSeparate) \
  X(PFNGLBLENDFUNCPROC, glBlendFunc) \
  X(PFNGLBLENDFUNCSEPARATEPROC, glBlendFuncSeparate) \
  X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer) \
  X(PFNGLBUFFERDATAPROC, glBufferData) \
  X(PFNGLBUFFERSUBDATAPROC, glBufferSubData) \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus) \
  X(PFNGLCLEARPROC, glClear) \
  X(PFNGLCLEARCOLORPROC, glClearColor) \
  X(PFNGLCLEARDEPTHPROC, glClearDepth) \
  X(PFNGLCOMPILESHADERPROC, glCompileShader) \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram) \
  X(PFNGLCREATESHADERPROC, glCreateShader) \
  X(PFNGLCULLFACEPROC, glCullFace) \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers) \
  X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers) \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram) \
  X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers) \
  X(PFNGLDELETESHADERPROC, glDeleteShader) \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures) \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays) \
  X(PFNGLDEPTHFUNCPROC, glDepthFunc) \
  X(PFNGLDEPTHMASKPROC, glDepthMask) \
  X(PFNGLDETACHSHADERPROC, glDetachShader) \
  X(PFNGLDISABLEPROC, glDisable) \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, glDisableVertexAttribArray) \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays) \
  X(PFNGLDRAWARRAYSINSTANCEDPROC, glDrawArraysInstanced) \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements) \
  X(PFNGLDRAWELEMENTSBASEVERTEXPROC, glDrawElementsBaseVertex) \
  X(PFNGLENABLEPROC, glEnable) \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray) \
  X(PFNGLFINISHPROC, glFinish) \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer) \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D) \
  X(PFNGLGENBUFFERSPROC, glGenBuffers) \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers) \
  X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers) \
  X(PFNGLGENTEXTURESPROC, glGenTextures) \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays) \
  X(PFNGLGETATTRIBLOCATIONPROC, glGetAttribLocation) \
  X(PFNGLGETERRORPROC, glGetError) \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv) \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog) \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv) \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog) \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv) \
  X(PFNGLGETSTRINGPROC, glGetString) \
  X(PFNGLGETSTRINGIPROC, glGetStringi) \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation) \
  X(PFNGLISENABLEDPROC, glIsEnabled) \
  X(PFNGLISPROGRAMPROC, glIsProgram) \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram) \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei) \
  X(PFNGLPOLYGONMODEPROC, glPolygonMode) \
  X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset) \
  X(PFNGLREADBUFFERPROC, glReadBuffer) \
  X(PFNGLREADPIXELSPROC, glReadPixels) \
  X(PFNGLRENDERBUFFERSTORAGEPROC, glRenderbufferStorage) \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, glRenderbufferStorageMultisample) \
  X(PFNGLSCISSORPROC, glScissor) \
  X(PFNGLSHADERSOURCEPROC, glShaderSource) \
  X(PFNGLTEXBUFFERPROC, glTexBuffer) \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D) \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri) \
  X(PFNGLUNIFORM1FPROC, glUniform1f) \
  X(PFNGLUNIFORM1IPROC, glUniform1i) \
  X(PFNGLUNIFORM2FPROC, glUniform2f) \
  X(PFNGLUNIFORM3FPROC, glUniform3f) \
  X(PFNGLUNIFORM3FVPROC, glUniform3fv) \
  X(PFNGLUNIFORM4FPROC, glUniform4f) \
  X(PFNGLUNIFORM4FVPROC, glUniform4fv) \
  X(PFNGLUNIFORMMATRIX3FVPROC, glUniformMatrix3fv) \
  X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv) \
  X(PFNGLUSEPROGRAMPROC, glUseProgram) \
  X(PFNGLVERTEXATTRIBDIVISORPROC, glVertexAttribDivisor) \
  X(PFNGLVERTEXATTRIBIPOINTERPROC, glVertexAttribIPointer) \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer) \
  X(PFNGLVIEWPORTPROC, glViewport)

namespace anisurf::gl {

#define ANISURF_GL_DECLARE(type, name) extern type name;
ANISURF_GL_FUNCTIONS(ANISURF_GL_DECLARE)
#undef ANISURF_GL_DECLARE

}  // namespace anisurf::gl
