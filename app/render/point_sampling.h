// Thinning a point set for display: at most N points spread over the set's
// extent (one per cell of a uniform grid, the cell as small as the cap
// allows), so that a capped set of markers still shows where the points are.
#pragma once
#include <glm/glm.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace anisurf::render {

// Indices (increasing) of at most `cap` of `points`: all of them when there
// are no more than `cap`, else the first point of each occupied cell of the
// finest grid (cells of a size tried from the bounding box's diagonal down
// by steps of 15%) that has at most `cap` occupied cells.
std::vector<std::size_t> spread_sample(std::span<const glm::vec3> points, std::size_t cap);

}  // namespace anisurf::render
