#include "render/gpu.h"

#include <glm/gtc/type_ptr.hpp>

#include <cstdio>

#include "render/shaders.h"

namespace anisurf::render {

using namespace anisurf::gl;

void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_renderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }

void check_gl(const char* where) {
  GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", e);
  throw GlError(std::string("OpenGL error ") + code + " in " + where);
}

namespace {

GLuint compile(GLenum type, std::string_view file) {
  std::string_view src = shader_source(file);
  if (src.empty()) throw GlError("shader '" + std::string(file) + "' is not embedded in the binary");
  GLuint s = glCreateShader(type);
  const char* text = src.data();
  GLint len = static_cast<GLint>(src.size());
  glShaderSource(s, 1, &text, &len);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(n > 0 ? n : 1), '\0');
    glGetShaderInfoLog(s, n, nullptr, log.data());
    glDeleteShader(s);
    throw GlError("cannot compile shader " + std::string(file) + ":\n" + log);
  }
  return s;
}

}  // namespace

Program::Program(std::string_view vertex_file, std::string_view fragment_file) {
  GLuint vs = compile(GL_VERTEX_SHADER, vertex_file);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment_file);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDetachShader(p, vs);
  glDetachShader(p, fs);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(n > 0 ? n : 1), '\0');
    glGetProgramInfoLog(p, n, nullptr, log.data());
    glDeleteProgram(p);
    throw GlError("cannot link " + std::string(vertex_file) + " + " + std::string(fragment_file) + ":\n" + log);
  }
  program_ = GlName<delete_program>(p);
}

void Program::use() const { glUseProgram(program_.id()); }

GLint Program::location(const char* name) {
  auto it = locations_.find(name);
  if (it != locations_.end()) return it->second;
  GLint loc = glGetUniformLocation(program_.id(), name);
  locations_.emplace(name, loc);
  return loc;
}

void Program::set(const char* name, int v) { glUniform1i(location(name), v); }
void Program::set(const char* name, float v) { glUniform1f(location(name), v); }
void Program::set(const char* name, const glm::vec2& v) { glUniform2f(location(name), v.x, v.y); }
void Program::set(const char* name, const glm::vec3& v) { glUniform3f(location(name), v.x, v.y, v.z); }
void Program::set(const char* name, const glm::vec4& v) { glUniform4f(location(name), v.x, v.y, v.z, v.w); }
void Program::set(const char* name, const glm::mat3& v) {
  glUniformMatrix3fv(location(name), 1, GL_FALSE, glm::value_ptr(v));
}
void Program::set(const char* name, const glm::mat4& v) {
  glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(v));
}

Buffer::Buffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  buffer_ = GlName<delete_buffer>(id);
}

void Buffer::upload(GLenum target, const void* data, std::size_t bytes, GLenum usage) {
  glBindBuffer(target, buffer_.id());
  glBufferData(target, static_cast<GLsizeiptr>(bytes), data, usage);
  size_ = bytes;
}

VertexArray::VertexArray() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  vao_ = GlName<delete_vertex_array>(id);
}

void VertexArray::bind() const { glBindVertexArray(vao_.id()); }

void VertexArray::attribute(GLuint index, const Buffer& buffer, int components, std::size_t stride,
                            std::size_t offset, GLuint divisor) {
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, buffer.id());
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, components, GL_FLOAT, GL_FALSE, static_cast<GLsizei>(stride),
                        reinterpret_cast<const void*>(offset));
  glVertexAttribDivisor(index, divisor);
}

BufferTexture::BufferTexture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  texture_ = GlName<delete_texture>(id);
}

void BufferTexture::upload(GLenum internal_format, const void* data, std::size_t bytes) {
  // A zero-sized buffer texture is not allowed: keep one dummy texel.
  static const unsigned char zero[16] = {};
  if (bytes == 0) {
    data = zero;
    bytes = sizeof zero;
  }
  buffer_.upload(GL_TEXTURE_BUFFER, data, bytes);
  glBindTexture(GL_TEXTURE_BUFFER, texture_.id());
  glTexBuffer(GL_TEXTURE_BUFFER, internal_format, buffer_.id());
  glBindTexture(GL_TEXTURE_BUFFER, 0);
}

void BufferTexture::bind(int unit) const {
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_BUFFER, texture_.id());
}

Texture2D::Texture2D() {
  GLuint id = 0;
  glGenTextures(1, &id);
  texture_ = GlName<delete_texture>(id);
}

void Texture2D::upload_rgba8(int width, int height, const unsigned char* pixels, bool linear) {
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  GLint filter = linear ? GL_LINEAR : GL_NEAREST;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void Texture2D::bind(int unit) const {
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_2D, texture_.id());
}

void RenderTarget::ensure(int width, int height, int samples) {
  if (fbo_ && width == width_ && height == height_ && samples == samples_) return;
  width_ = width;
  height_ = height;
  samples_ = samples;
  GLuint ids[2] = {0, 0};
  GLuint fbo = 0;
  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(2, ids);
  fbo_ = GlName<delete_framebuffer>(fbo);
  color_ = GlName<delete_renderbuffer>(ids[0]);
  depth_ = GlName<delete_renderbuffer>(ids[1]);
  auto storage = [&](GLenum format) {
    if (samples > 1)
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
      glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
  };
  glBindRenderbuffer(GL_RENDERBUFFER, color_.id());
  storage(GL_RGBA8);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_.id());
  storage(GL_DEPTH_COMPONENT24);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
  GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("offscreen framebuffer " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                  std::to_string(samples) + " samples is incomplete (status " + std::to_string(status) + ")");
}

void RenderTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id()); }

void RenderTarget::resolve(GLuint target) const { resolve(target, width_, height_); }

void RenderTarget::resolve(GLuint target, int target_width, int target_height) const {
  const bool scaled = target_width != width_ || target_height != height_;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.id());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, target_width, target_height, GL_COLOR_BUFFER_BIT,
                    scaled ? GL_LINEAR : GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, target);
}

}  // namespace anisurf::render
