#include "render/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"

namespace anisurf::render {

void Image::flip_rows() {
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(rgba.begin() + static_cast<std::ptrdiff_t>(y * row),
                     rgba.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                     rgba.begin() + static_cast<std::ptrdiff_t>((height - 1 - y) * row));
}

std::vector<std::uint8_t> encode_png(const Image& image) {
  std::vector<std::uint8_t> out;
  auto sink = [](void* context, void* data, int size) {
    auto* v = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* p = static_cast<const std::uint8_t*>(data);
    v->insert(v->end(), p, p + size);
  };
  if (!stbi_write_png_to_func(sink, &out, image.width, image.height, 4, image.rgba.data(), image.width * 4))
    throw IoError("PNG encoding failed for a " + std::to_string(image.width) + "x" +
                  std::to_string(image.height) + " image");
  return out;
}

void write_png(const std::string& path, const Image& image) {
  std::vector<std::uint8_t> bytes = encode_png(image);
  AtomicFile file(path);
  file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.commit();
}

Image read_png(const std::string& path) {
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  if (!data) throw IoError(path + ": cannot read image (" + std::string(stbi_failure_reason()) + ")");
  Image img(w, h);
  std::copy(data, data + img.rgba.size(), img.rgba.begin());
  stbi_image_free(data);
  return img;
}

double mean_abs_diff(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("mean_abs_diff: sizes differ (" + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height) + ")");
  if (a.empty()) return 0.0;
  double sum = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4)
    for (int k = 0; k < 3; ++k) sum += std::abs(int(a.rgba[i + k]) - int(b.rgba[i + k]));
  return sum / (3.0 * static_cast<double>(a.width) * static_cast<double>(a.height));
}

Coverage foreground(const Image& image, const std::uint8_t background[3], int tolerance) {
  Coverage c;
  double sx = 0, sy = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      bool fg = false;
      for (int k = 0; k < 3; ++k) fg |= std::abs(int(p[k]) - int(background[k])) > tolerance;
      if (!fg) continue;
      ++c.count;
      sx += x + 0.5;
      sy += y + 0.5;
    }
  if (c.count) {
    c.cx = sx / static_cast<double>(c.count);
    c.cy = sy / static_cast<double>(c.count);
  }
  if (!image.empty()) c.fraction = static_cast<double>(c.count) / (double(image.width) * double(image.height));
  return c;
}

}  // namespace anisurf::render
