// Colormaps for scalar fields, sampled into a 256-texel texture for the GPU
// and used directly by the legend.
//  - viridis: perceptually uniform sequential map (van der Walt & Smith,
//    CC0), piecewise linear through its published key colours;
//  - coolwarm: diverging blue - grey - red (Moreland's end points),
//    interpolated in CIELAB so that lightness changes evenly;
//  - categorical: distinct colours for integer labels (references).
#pragma once
#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anisurf::render {

enum class Colormap { Viridis, Coolwarm };

std::optional<Colormap> parse_colormap(std::string_view name);
const char* colormap_name(Colormap c);

// Colour at t in [0, 1] (clamped), linear RGB components in [0, 1] of the
// sRGB-encoded colour (the values written to the framebuffer).
glm::vec3 colormap_color(Colormap c, float t);

// n samples from t = 0 to 1 as RGBA8 (for a texture).
std::vector<unsigned char> colormap_rgba8(Colormap c, int n = 256);

// Colour of integer label `label` (deterministic; neighbouring labels differ
// strongly). The first 12 are a hand-picked qualitative palette.
glm::vec3 categorical_color(int label);

}  // namespace anisurf::render
