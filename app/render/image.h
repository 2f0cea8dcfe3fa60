// RGBA8 images: PNG encoding (stb_image_write, written through a temporary
// file renamed on success), decoding (stb_image, for tests and comparisons)
// and the measures the tests use on rendered pictures.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace anisurf::render {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // rows top-down, 4 bytes per pixel

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4) {}
  bool empty() const { return width == 0 || height == 0; }
  const std::uint8_t* pixel(int x, int y) const { return &rgba[4 * (static_cast<std::size_t>(y) * width + x)]; }
  std::uint8_t* pixel(int x, int y) { return &rgba[4 * (static_cast<std::size_t>(y) * width + x)]; }
  // Reverses the row order (GL reads rows bottom-up).
  void flip_rows();
};

// PNG bytes of the image (deterministic for equal pixels).
std::vector<std::uint8_t> encode_png(const Image& image);
// Writes a PNG through "<path>.tmp-<pid>" renamed over `path`; throws IoError.
void write_png(const std::string& path, const Image& image);
// Reads a PNG (or any format stb_image knows) as RGBA8; throws IoError.
Image read_png(const std::string& path);

// Mean absolute difference of the RGB channels, in [0, 255]; images must have
// the same size (throws std::invalid_argument otherwise).
double mean_abs_diff(const Image& a, const Image& b);

// Pixels whose RGB differs from `background` by more than `tolerance` in some
// channel: their count and centroid (pixel units, origin top-left).
struct Coverage {
  std::size_t count = 0;
  double cx = 0, cy = 0;
  double fraction = 0;  // count / (width * height)
};
Coverage foreground(const Image& image, const std::uint8_t background[3], int tolerance = 8);

}  // namespace anisurf::render
