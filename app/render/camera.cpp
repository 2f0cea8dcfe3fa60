#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace anisurf::render {

namespace {
constexpr std::array<std::pair<NamedView, const char*>, 7> kViews = {{{NamedView::Iso, "iso"},
                                                                      {NamedView::Front, "front"},
                                                                      {NamedView::Back, "back"},
                                                                      {NamedView::Top, "top"},
                                                                      {NamedView::Bottom, "bottom"},
                                                                      {NamedView::Left, "left"},
                                                                      {NamedView::Right, "right"}}};
constexpr float kHalfPi = 1.57079632679f;
}  // namespace

std::optional<NamedView> parse_view(std::string_view name) {
  for (const auto& [v, n] : kViews)
    if (name == n) return v;
  return std::nullopt;
}

const char* view_name(NamedView v) {
  for (const auto& [w, n] : kViews)
    if (v == w) return n;
  return "?";
}

std::string view_names() {
  std::string s;
  for (const auto& [v, n] : kViews) {
    if (!s.empty()) s += '|';
    s += n;
  }
  return s;
}

glm::mat3 Camera::frame() const {
  if (up_axis == UpAxis::Y) return glm::mat3(1.0f);
  // Local (x, y, z) with y up -> world (x, -z, y): local +z ("front") is
  // world -y, local +y is world +z.
  return glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0));
}

glm::vec3 Camera::forward() const {
  // In the local frame the eye sits at (cos p sin y, sin p, cos p cos y).
  glm::vec3 to_eye(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
  return -(frame() * to_eye);
}

glm::vec3 Camera::right() const { return frame() * glm::vec3(std::cos(yaw), 0.0f, -std::sin(yaw)); }

glm::vec3 Camera::up() const { return glm::normalize(glm::cross(right(), forward())); }

glm::vec3 Camera::eye() const { return target - forward() * distance; }

glm::mat4 Camera::view() const {
  glm::vec3 f = forward(), r = right(), u = up(), e = eye();
  glm::mat4 m(1.0f);
  m[0][0] = r.x; m[1][0] = r.y; m[2][0] = r.z;
  m[0][1] = u.x; m[1][1] = u.y; m[2][1] = u.z;
  m[0][2] = -f.x; m[1][2] = -f.y; m[2][2] = -f.z;
  m[3][0] = -glm::dot(r, e);
  m[3][1] = -glm::dot(u, e);
  m[3][2] = glm::dot(f, e);
  return m;
}

glm::mat4 Camera::projection(float aspect) const {
  const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(shift_x, 0.0f, 0.0f));
  return shift * centred_projection(aspect);
}

glm::mat4 Camera::centred_projection(float aspect) const {
  // Near / far enclose the scene's bounding sphere around the target (the
  // target stays near the scene centre: pan moves it in the view plane).
  float reach = scene_radius * 2.0f + glm::length(target) * 1e-6f;
  float far_plane = distance + reach;
  if (orthographic) {
    float h = ortho_half_height;
    return glm::ortho(-h * aspect, h * aspect, -h, h, std::max(distance - reach, -far_plane), far_plane);
  }
  float near_plane = std::max(distance - reach, far_plane * 1e-4f);
  return glm::perspective(fov_y, aspect, near_plane, far_plane);
}

void Camera::orbit(float dyaw, float dpitch) {
  yaw = std::remainder(yaw + dyaw, 2.0f * glm::pi<float>());
  pitch = std::clamp(pitch + dpitch, -kHalfPi, kHalfPi);
}

void Camera::pan(float dx_fraction, float dy_fraction) {
  float h = orthographic ? 2.0f * ortho_half_height : 2.0f * distance * std::tan(fov_y * 0.5f);
  target += (-dx_fraction * right() - dy_fraction * up()) * h;
}

void Camera::zoom(float factor) {
  if (orthographic)
    ortho_half_height = std::max(ortho_half_height * factor, scene_radius * 1e-5f);
  else
    distance = std::max(distance * factor, scene_radius * 1e-4f);
}

void Camera::set_view(NamedView v) {
  switch (v) {
    case NamedView::Iso:
      yaw = glm::radians(45.0f);
      pitch = std::atan(1.0f / std::sqrt(2.0f));  // 35.26 deg: the cube diagonal
      break;
    case NamedView::Front: yaw = 0; pitch = 0; break;
    case NamedView::Back: yaw = glm::pi<float>(); pitch = 0; break;
    case NamedView::Right: yaw = kHalfPi; pitch = 0; break;
    case NamedView::Left: yaw = -kHalfPi; pitch = 0; break;
    case NamedView::Top: yaw = 0; pitch = kHalfPi; break;
    case NamedView::Bottom: yaw = 0; pitch = -kHalfPi; break;
  }
}

void Camera::look_along(const glm::vec3& direction) {
  const float len = glm::length(direction);
  if (!(len > 0.0f)) return;
  // forward() = -(frame() * to_eye) with to_eye = (cos p sin y, sin p, cos p cos y).
  const glm::vec3 to_eye = glm::transpose(frame()) * (-direction / len);
  pitch = std::asin(std::clamp(to_eye.y, -1.0f, 1.0f));
  if (std::abs(to_eye.x) + std::abs(to_eye.z) > 1e-7f) yaw = std::atan2(to_eye.x, to_eye.z);
}

void Camera::fit(std::span<const glm::vec3> points, float aspect, float margin, float reserve_left,
                 float reserve_right) {
  if (points.empty()) return;
  reserve_left = std::clamp(reserve_left, 0.0f, 0.45f);
  reserve_right = std::clamp(reserve_right, 0.0f, 0.45f);
  shift_x = reserve_left - reserve_right;
  aspect *= 1.0f - reserve_left - reserve_right;  // the free part of the view
  glm::vec3 r = right(), u = up(), f = forward();
  // Extents in the camera axes.
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : points) {
    glm::vec3 c(glm::dot(p, r), glm::dot(p, u), glm::dot(p, f));
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  glm::vec3 mid = 0.5f * (lo + hi);
  glm::vec3 half = 0.5f * (hi - lo);
  scene_radius = std::max(glm::length(half), 1e-12f);
  float s = 1.0f + 2.0f * margin;
  // Centre of the projected extents on screen, depth centre along the view.
  target = mid.x * r + mid.y * u + mid.z * f;
  // Orthographic: the half height holding both extents.
  ortho_half_height = std::max(half.y, half.x / aspect) * s;
  if (ortho_half_height <= 0) ortho_half_height = scene_radius;
  // Perspective: every point p (offsets x, y from the axis, depth z toward
  // the eye) needs distance >= z + |x| / tan(fovx/2) and z + |y| / tan(fovy/2).
  // Near points look bigger, so the target is then moved sideways until the
  // projected extents are centred (a few fixed-point steps).
  float ty = std::tan(fov_y * 0.5f) / s;
  float tx = ty * aspect;
  auto tight_distance = [&] {
    float d = 0;
    for (const glm::vec3& p : points) {
      glm::vec3 q = p - target;
      float x = std::abs(glm::dot(q, r)), y = std::abs(glm::dot(q, u)), z = -glm::dot(q, f);
      d = std::max({d, z + x / tx, z + y / ty});
    }
    return d;
  };
  float d = tight_distance();
  for (int step = 0; step < 4 && !orthographic && d > 0; ++step) {
    float xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (const glm::vec3& p : points) {
      glm::vec3 q = p - target;
      float depth = d + glm::dot(q, f);  // distance in front of the eye
      if (depth <= 0) continue;
      float sx = glm::dot(q, r) / depth, sy = glm::dot(q, u) / depth;
      xlo = std::min(xlo, sx);
      xhi = std::max(xhi, sx);
      ylo = std::min(ylo, sy);
      yhi = std::max(yhi, sy);
    }
    if (!(xlo <= xhi)) break;
    target += (0.5f * (xlo + xhi) * r + 0.5f * (ylo + yhi) * u) * d;
    d = tight_distance();
  }
  distance = std::max(d, scene_radius * 1e-3f);
  // The ortho eye sits outside the scene too (for the near plane).
  if (orthographic) distance = std::max(distance, 2.0f * scene_radius);
}

}  // namespace anisurf::render
