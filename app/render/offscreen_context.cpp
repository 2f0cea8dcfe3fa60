// The only source file that includes <GL/osmesa.h> (it pulls <GL/gl.h>, whose
// prototypes would clash with the loader's names in render/gl.h).
//
// libOSMesa is opened with dlopen(RTLD_LOCAL) rather than linked: its ~1300
// exported gl* symbols then never enter the global symbol scope, so they cannot
// interpose on the libGL that GLFW loads for the window backend, and a window
// session never loads the (large, LLVM-backed) OSMesa library at all.
#include "render/offscreen_context.h"

#include <GL/osmesa.h>
#include <dlfcn.h>

#include <vector>

#include "render/gl_load.h"
#include "render/gpu_error.h"

namespace anisurf::render {

namespace {

struct OsMesaApi {
  decltype(&OSMesaCreateContextAttribs) create_context_attribs = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaDestroyContext) destroy_context = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc_address = nullptr;
};

// Opened once per process and never closed (llvmpipe keeps worker threads).
const OsMesaApi& osmesa_api() {
  static const OsMesaApi api = [] {
    OsMesaApi a;
    void* lib = nullptr;
    std::string tried;
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
      lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
      if (lib) break;
      tried += std::string(tried.empty() ? "" : ", ") + name;
    }
    if (!lib)
      throw GlError("cannot load OSMesa for headless rendering (tried " + tried +
                     "): install the Debian package libosmesa6");
    a.create_context_attribs =
        reinterpret_cast<decltype(a.create_context_attribs)>(dlsym(lib, "OSMesaCreateContextAttribs"));
    a.make_current = reinterpret_cast<decltype(a.make_current)>(dlsym(lib, "OSMesaMakeCurrent"));
    a.destroy_context = reinterpret_cast<decltype(a.destroy_context)>(dlsym(lib, "OSMesaDestroyContext"));
    a.get_proc_address = reinterpret_cast<decltype(a.get_proc_address)>(dlsym(lib, "OSMesaGetProcAddress"));
    if (!a.create_context_attribs || !a.make_current || !a.destroy_context || !a.get_proc_address)
      throw GlError("libOSMesa lacks OSMesaCreateContextAttribs (Mesa >= 12 needed)");
    return a;
  }();
  return api;
}

// OSMesaGetProcAddress has the signature of the loader (name -> function).
const OsMesaApi* g_api_for_loader = nullptr;
gl::ProcAddress get_proc(const char* name) {
  return reinterpret_cast<gl::ProcAddress>(g_api_for_loader->get_proc_address(name));
}

}  // namespace

struct OffscreenContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> buffer;
  int width = 0, height = 0;
};

OffscreenContext::OffscreenContext(int width, int height) : impl_(std::make_unique<Impl>()) {
  const OsMesaApi& api = osmesa_api();
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  impl_->context = api.create_context_attribs(attribs, nullptr);
  if (!impl_->context) throw GlError("OSMesa could not create an OpenGL 3.3 core context");
  resize(width, height);
  g_api_for_loader = &api;
  auto missing = gl::load_gl(&get_proc);
  if (!missing.empty())
    throw GlError("OSMesa lacks OpenGL function " + missing.front() + " (" + std::to_string(missing.size()) +
                   " missing): OpenGL 3.3 core is required");
}

OffscreenContext::~OffscreenContext() {
  if (impl_->context) osmesa_api().destroy_context(impl_->context);
}

void OffscreenContext::resize(int width, int height) {
  if (width < 1 || height < 1) throw GlError("offscreen buffer size must be positive");
  impl_->buffer.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  impl_->width = width;
  impl_->height = height;
  if (!osmesa_api().make_current(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, width, height))
    throw GlError("OSMesaMakeCurrent failed for a " + std::to_string(width) + "x" + std::to_string(height) +
                   " buffer (larger than the maximum?)");
}

int OffscreenContext::width() const { return impl_->width; }
int OffscreenContext::height() const { return impl_->height; }

}  // namespace anisurf::render
