#include "render/point_sampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace anisurf::render {

namespace {

// The first point of each occupied cell of size `cell` (grid anchored at
// `lo`), by increasing index.
std::vector<std::size_t> one_per_cell(std::span<const glm::vec3> points, const glm::vec3& lo, float cell) {
  std::unordered_map<std::uint64_t, std::size_t> first;
  first.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec3 c = glm::floor((points[i] - lo) / cell);
    // 21 bits per axis: enough cells for any cap this is used with.
    const auto key = (static_cast<std::uint64_t>(c.x) & 0x1fffff) | (static_cast<std::uint64_t>(c.y) & 0x1fffff) << 21 |
                     (static_cast<std::uint64_t>(c.z) & 0x1fffff) << 42;
    first.try_emplace(key, i);
  }
  std::vector<std::size_t> kept;
  kept.reserve(first.size());
  for (const auto& [key, i] : first) kept.push_back(i);
  std::sort(kept.begin(), kept.end());
  return kept;
}

}  // namespace

std::vector<std::size_t> spread_sample(std::span<const glm::vec3> points, std::size_t cap) {
  std::vector<std::size_t> all(points.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  if (points.size() <= cap) return all;
  if (cap == 0) return {};
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float diagonal = glm::length(hi - lo);
  if (!(diagonal > 0.0f)) return {0};  // all at one place
  std::vector<std::size_t> best = {0};
  for (float cell = diagonal; cell > diagonal * 1e-6f; cell *= 0.85f) {
    std::vector<std::size_t> kept = one_per_cell(points, lo, cell);
    if (kept.size() > cap) break;
    best = std::move(kept);
  }
  return best;
}

}  // namespace anisurf::render
