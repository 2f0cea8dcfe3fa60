// A turntable camera around a target point: yaw about the world's up axis,
// pitch about the camera's right axis (clamped to +-90 degrees, so the views
// from the top and the bottom are valid), distance to the target, perspective
// or orthographic projection. Named views and fitting to a point set.
#pragma once
#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace anisurf::render {

enum class UpAxis { Y, Z };
enum class NamedView { Iso, Front, Back, Top, Bottom, Left, Right };

// Parses "iso", "front", ... (empty optional on an unknown name).
std::optional<NamedView> parse_view(std::string_view name);
const char* view_name(NamedView v);
// "iso|front|back|top|bottom|left|right"
std::string view_names();

class Camera {
 public:
  // --- state ----------------------------------------------------------------
  glm::vec3 target{0.0f};
  float distance = 1.0f;       // eye to target (perspective); also the eye offset in ortho
  float yaw = 0.0f;            // radians about the up axis; 0: looking from +front
  float pitch = 0.0f;          // radians, in [-pi/2, pi/2]; +: looking down
  float fov_y = glm::radians(35.0f);  // perspective vertical field of view
  float ortho_half_height = 1.0f;     // orthographic half height of the view
  bool orthographic = false;
  UpAxis up_axis = UpAxis::Y;
  float scene_radius = 1.0f;   // bounding radius of the scene (near/far planes)
  // Horizontal shift of the picture in normalised device units (off-axis
  // projection): l - r centres the view between a strip l of the width on
  // the left (the panel) and r on the right (the legend).
  float shift_x = 0.0f;

  // --- matrices -------------------------------------------------------------
  glm::vec3 eye() const;
  glm::vec3 forward() const;  // unit, eye -> target
  glm::vec3 right() const;    // unit, screen x
  glm::vec3 up() const;       // unit, screen y
  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;

  // --- interaction ----------------------------------------------------------
  // Turntable rotation by angles in radians (from a mouse drag).
  void orbit(float dyaw, float dpitch);
  // Moves the target in the view plane by a fraction of the view height.
  void pan(float dx_fraction, float dy_fraction);
  // Multiplies the distance (perspective) or the view height (ortho) by factor.
  void zoom(float factor);
  void set_view(NamedView v);
  // Turns the camera so that it looks along `direction` (world, any length
  // > 0): yaw and pitch of the turntable that give that forward(). The
  // target and the distance stay.
  void look_along(const glm::vec3& direction);

  // Places target and distance / ortho height so that every point is inside
  // the view (aspect = width / height) with a relative margin, keeping the
  // orientation. Points are in world coordinates. reserve_left / _right:
  // fractions of the width kept free on each side (sets shift_x).
  void fit(std::span<const glm::vec3> points, float aspect, float margin = 0.06f, float reserve_left = 0.0f,
           float reserve_right = 0.0f);

 private:
  glm::mat4 centred_projection(float aspect) const;
  // World-from-"Y up" rotation for the up axis.
  glm::mat3 frame() const;
};

}  // namespace anisurf::render
