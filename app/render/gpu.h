// Small RAII wrappers over the OpenGL objects the renderer uses (programs,
// buffers, vertex arrays, textures, framebuffers). Each owns one GL name and
// deletes it on destruction; they are movable, not copyable. A current context
// with the GL functions loaded (render/gl.h) is required for every call.
#pragma once
#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "render/gl.h"
#include "render/gpu_error.h"

namespace anisurf::render {

// Owner of one GL name; Deleter is called with the name when non-zero.
template <void (*Deleter)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  ~GlName() { reset(); }
  GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) { reset(); id_ = std::exchange(o.id_, 0); }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Deleter(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void delete_buffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_renderbuffer(GLuint id);
void delete_program(GLuint id);

// A linked program from two embedded shader files (render/shaders.h). Throws
// GlError with the compiler's log (and the file name) on failure.
class Program {
 public:
  Program() = default;
  Program(std::string_view vertex_file, std::string_view fragment_file);
  void use() const;
  GLuint id() const { return program_.id(); }
  // Uniform setters; unknown names (optimised away) are ignored.
  void set(const char* name, int v);
  void set(const char* name, float v);
  void set(const char* name, const glm::vec2& v);
  void set(const char* name, const glm::vec3& v);
  void set(const char* name, const glm::vec4& v);
  void set(const char* name, const glm::mat3& v);
  void set(const char* name, const glm::mat4& v);

 private:
  GLint location(const char* name);
  GlName<delete_program> program_;
  std::unordered_map<std::string, GLint> locations_;
};

// A buffer object; upload() replaces its content (and size).
class Buffer {
 public:
  Buffer();
  void upload(GLenum target, const void* data, std::size_t bytes, GLenum usage = GL_STATIC_DRAW);
  GLuint id() const { return buffer_.id(); }
  std::size_t size() const { return size_; }

 private:
  GlName<delete_buffer> buffer_;
  std::size_t size_ = 0;
};

class VertexArray {
 public:
  VertexArray();
  void bind() const;
  // Float attribute `index` read from `buffer` (bound as GL_ARRAY_BUFFER);
  // divisor 1 makes it per instance.
  void attribute(GLuint index, const Buffer& buffer, int components, std::size_t stride, std::size_t offset,
                 GLuint divisor = 0);

 private:
  GlName<delete_vertex_array> vao_;
};

// A buffer texture (samplerBuffer / usamplerBuffer in GLSL): per-triangle data
// indexed by gl_PrimitiveID.
class BufferTexture {
 public:
  BufferTexture();
  // `internal_format`: GL_R32F, GL_RGBA8, GL_R8UI ...
  void upload(GLenum internal_format, const void* data, std::size_t bytes);
  void bind(int unit) const;
  bool empty() const { return buffer_.size() == 0; }

 private:
  Buffer buffer_;
  GlName<delete_texture> texture_;
};

// A 2D RGBA8 texture (colormaps: width x 1, linear filtering, clamped).
class Texture2D {
 public:
  Texture2D();
  void upload_rgba8(int width, int height, const unsigned char* pixels, bool linear);
  void bind(int unit) const;

 private:
  GlName<delete_texture> texture_;
};

// An offscreen render target: RGBA8 colour + 24-bit depth renderbuffers,
// multisampled when samples > 1. resolve() blits it into another framebuffer.
class RenderTarget {
 public:
  RenderTarget() = default;
  // (Re)allocates when the size or sample count changed.
  void ensure(int width, int height, int samples);
  void bind() const;
  // Blits the colour into framebuffer `target` (0: the default one).
  void resolve(GLuint target) const;
  // Blits the colour into the target_width x target_height framebuffer
  // `target`, filtered linearly when the sizes differ (single-sample only).
  void resolve(GLuint target, int target_width, int target_height) const;
  // Blits the colour into `other` (same size; resolves the samples).
  void resolve_into(const RenderTarget& other) const { resolve(other.fbo_.id(), other.width_, other.height_); }
  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }

 private:
  GlName<delete_framebuffer> fbo_;
  GlName<delete_renderbuffer> color_;
  GlName<delete_renderbuffer> depth_;
  int width_ = 0, height_ = 0, samples_ = 0;
};

// Throws GlError naming `where` if glGetError() reports an error.
void check_gl(const char* where);

}  // namespace anisurf::render
