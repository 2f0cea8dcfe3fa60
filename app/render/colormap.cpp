#include "render/colormap.h"

#include <algorithm>
#include <cmath>

namespace anisurf::render {

namespace {

// Viridis at t = 0, 1/8, ..., 1 (the map's published 9-step palette).
constexpr std::array<unsigned, 9> kViridis = {0x440154, 0x472c7a, 0x3b518b, 0x2c718e, 0x21908d,
                                              0x27ad81, 0x5cc863, 0xaadc32, 0xfde725};

glm::vec3 hex(unsigned c) {
  return glm::vec3((c >> 16) & 0xff, (c >> 8) & 0xff, c & 0xff) / 255.0f;
}

glm::vec3 piecewise(const unsigned* keys, int n, float t) {
  float x = std::clamp(t, 0.0f, 1.0f) * static_cast<float>(n - 1);
  int i = std::min(static_cast<int>(x), n - 2);
  return glm::mix(hex(keys[i]), hex(keys[i + 1]), x - static_cast<float>(i));
}

// sRGB <-> CIELAB (D65), for the diverging map.
float to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
constexpr glm::vec3 kWhite(0.95047f, 1.0f, 1.08883f);
float lab_f(float t) { return t > 0.008856f ? std::cbrt(t) : 7.787f * t + 16.0f / 116.0f; }
float lab_finv(float t) { return t > 0.206893f ? t * t * t : (t - 16.0f / 116.0f) / 7.787f; }

glm::vec3 srgb_to_lab(glm::vec3 c) {
  glm::vec3 l(to_linear(c.r), to_linear(c.g), to_linear(c.b));
  glm::vec3 xyz(0.4124f * l.r + 0.3576f * l.g + 0.1805f * l.b, 0.2126f * l.r + 0.7152f * l.g + 0.0722f * l.b,
                0.0193f * l.r + 0.1192f * l.g + 0.9505f * l.b);
  glm::vec3 f(lab_f(xyz.x / kWhite.x), lab_f(xyz.y / kWhite.y), lab_f(xyz.z / kWhite.z));
  return {116.0f * f.y - 16.0f, 500.0f * (f.x - f.y), 200.0f * (f.y - f.z)};
}

glm::vec3 lab_to_srgb(glm::vec3 lab) {
  float fy = (lab.x + 16.0f) / 116.0f, fx = fy + lab.y / 500.0f, fz = fy - lab.z / 200.0f;
  glm::vec3 xyz(kWhite.x * lab_finv(fx), kWhite.y * lab_finv(fy), kWhite.z * lab_finv(fz));
  glm::vec3 l(3.2406f * xyz.x - 1.5372f * xyz.y - 0.4986f * xyz.z,
              -0.9689f * xyz.x + 1.8758f * xyz.y + 0.0415f * xyz.z,
              0.0557f * xyz.x - 0.2040f * xyz.y + 1.0570f * xyz.z);
  return {to_srgb(l.r), to_srgb(l.g), to_srgb(l.b)};
}

glm::vec3 coolwarm(float t) {
  // Moreland's end points and a light neutral centre.
  static const glm::vec3 lo = srgb_to_lab(hex(0x3b4cc0)), mid = srgb_to_lab(hex(0xdddddd)),
                         hi = srgb_to_lab(hex(0xb40426));
  t = std::clamp(t, 0.0f, 1.0f);
  return t < 0.5f ? lab_to_srgb(glm::mix(lo, mid, 2.0f * t)) : lab_to_srgb(glm::mix(mid, hi, 2.0f * t - 1.0f));
}

constexpr std::array<unsigned, 12> kCategorical = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f, 0xedc948,
                                                   0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac, 0x1f77b4, 0x8c564b};

}  // namespace

std::optional<Colormap> parse_colormap(std::string_view name) {
  if (name == "viridis") return Colormap::Viridis;
  if (name == "coolwarm") return Colormap::Coolwarm;
  return std::nullopt;
}

const char* colormap_name(Colormap c) { return c == Colormap::Viridis ? "viridis" : "coolwarm"; }

glm::vec3 colormap_color(Colormap c, float t) {
  if (c == Colormap::Viridis) return piecewise(kViridis.data(), static_cast<int>(kViridis.size()), t);
  return coolwarm(t);
}

std::vector<unsigned char> colormap_rgba8(Colormap c, int n) {
  std::vector<unsigned char> out(static_cast<std::size_t>(n) * 4);
  for (int i = 0; i < n; ++i) {
    glm::vec3 rgb = colormap_color(c, n > 1 ? static_cast<float>(i) / static_cast<float>(n - 1) : 0.0f);
    for (int k = 0; k < 3; ++k)
      out[4 * static_cast<std::size_t>(i) + k] = static_cast<unsigned char>(std::lround(rgb[k] * 255.0f));
    out[4 * static_cast<std::size_t>(i) + 3] = 255;
  }
  return out;
}

glm::vec3 categorical_color(int label) {
  unsigned u = static_cast<unsigned>(label);
  if (u < kCategorical.size()) return hex(kCategorical[u]);
  // Beyond the palette: golden-ratio hue steps at fixed saturation / value.
  float h = std::fmod(0.13f + 0.61803398875f * static_cast<float>(u), 1.0f) * 6.0f;
  float s = 0.55f, v = 0.85f;
  int i = static_cast<int>(h);
  float f = h - static_cast<float>(i), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i % 6) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

}  // namespace anisurf::render
