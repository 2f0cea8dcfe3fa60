#include "locate/aabb_tree.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/parallel_chunks.h"

namespace anisurf {

namespace {

constexpr int kBins = 16;
constexpr int kSahDepthLimit = 48;  // deeper nodes are split at the median (bounded depth)

double half_area(const BBox& b) {
  if (b.empty()) return 0;
  const Vec3 e = b.hi - b.lo;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

float round_down(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
}

// Grows a to hold b. Plain comparisons (min_of's NaN test is not needed:
// a starts empty, at +-inf, and is never NaN, and a NaN coordinate of b
// leaves a's as it is, as with min_of and max_of).
inline void merge(BBox& a, const BBox& b) {
  for (int k = 0; k < 3; ++k) {
    a.lo[k] = b.lo[k] < a.lo[k] ? b.lo[k] : a.lo[k];
    a.hi[k] = b.hi[k] > a.hi[k] ? b.hi[k] : a.hi[k];
  }
}
inline void add_point(BBox& a, const Vec3& p) {
  for (int k = 0; k < 3; ++k) {
    a.lo[k] = p[k] < a.lo[k] ? p[k] : a.lo[k];
    a.hi[k] = p[k] > a.hi[k] ? p[k] : a.hi[k];
  }
}

using Node = AabbTree::Node;
struct Task {
  int node, begin, end, depth;
};
// Subtrees of the root are built on two threads from this many primitives.
constexpr std::size_t kParallelBuild = 65536;

// One node of the build: its box, then a leaf, or the split of its
// primitives (binned SAH, median where that cannot separate them) into two
// children pushed onto `tasks`. `nodes` holds the node; `ids` the
// primitives, partitioned in place (task's range only).
void split_task(const Task& task, const std::vector<BBox>& boxes, const std::vector<std::array<double, 3>>& centre,
                int* ids, std::vector<Node>& nodes, std::vector<Task>& tasks, int& depth) {
  constexpr int kMaxLeafSize = AabbTree::kMaxLeafSize;
  depth = std::max(depth, task.depth);
  BBox box, cbox;
  for (int i = task.begin; i < task.end; ++i) {
    merge(box, boxes[ids[i]]);
    const std::array<double, 3>& c = centre[ids[i]];
    add_point(cbox, Vec3{c[0], c[1], c[2]});
  }
  for (int k = 0; k < 3; ++k) {
    nodes[task.node].lo[k] = round_down(box.lo[k]);
    nodes[task.node].hi[k] = round_up(box.hi[k]);
  }
  const int n = task.end - task.begin;
  auto make_leaf = [&] {
    nodes[task.node].first = task.begin;
    nodes[task.node].count = n;
  };
  // Four primitives or fewer make a leaf: half the nodes of leaves of two
  // (a node is 32 bytes) and as fast a search (the four tests cost what
  // the two levels of boxes above them would).
  if (n <= 4) {
    make_leaf();
    return;
  }

  // Choose the split: binned SAH over the three axes.
  int axis = -1, split_bin = -1;
  double best_cost = INFINITY;
  const Vec3 extent = cbox.hi - cbox.lo;
  if (task.depth < kSahDepthLimit) {
    // The bins of the three axes in one sweep over the primitives.
    std::array<std::array<BBox, kBins>, 3> bin_boxes{};
    std::array<std::array<int, kBins>, 3> bin_counts{};
    // The axes along which the centroids spread, their origins and scales.
    std::array<int, 3> axes{};
    std::array<double, 3> origin{}, scales{};
    int n_axes = 0;
    for (int a = 0; a < 3; ++a)
      if (extent[a] > 0) {
        axes[n_axes] = a;
        origin[n_axes] = cbox.lo[a];
        scales[n_axes++] = kBins / extent[a];
      }
    for (int i = task.begin; i < task.end; ++i) {
      const int id = ids[i];
      const std::array<double, 3>& c = centre[id];
      for (int j = 0; j < n_axes; ++j) {
        const int a = axes[j];
        const int b = std::min(kBins - 1, static_cast<int>((c[a] - origin[j]) * scales[j]));
        ++bin_counts[a][b];
        merge(bin_boxes[a][b], boxes[id]);
      }
    }
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0)) continue;
      const std::array<BBox, kBins>& bin_box = bin_boxes[a];
      const std::array<int, kBins>& bin_count = bin_counts[a];
      // Sweep from the right for the right-hand areas, then from the left.
      std::array<double, kBins> right_area{};
      std::array<int, kBins> right_count{};
      BBox acc;
      int cnt = 0;
      for (int b = kBins - 1; b > 0; --b) {
        merge(acc, bin_box[b]);
        cnt += bin_count[b];
        right_area[b] = half_area(acc);
        right_count[b] = cnt;
      }
      acc = BBox();
      cnt = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        merge(acc, bin_box[b]);
        cnt += bin_count[b];
        if (cnt == 0 || right_count[b + 1] == 0) continue;
        const double cost = cnt * half_area(acc) + right_count[b + 1] * right_area[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          axis = a;
          split_bin = b;
        }
      }
    }
  }
  const double leaf_cost = n * half_area(box);
  if (n <= kMaxLeafSize && !(best_cost < leaf_cost)) {
    make_leaf();
    return;
  }

  int mid = -1;
  if (axis >= 0) {
    const double scale = kBins / extent[axis];
    const double lo = cbox.lo[axis];
    int* part = std::partition(ids + task.begin, ids + task.end, [&](int id) {
      return std::min(kBins - 1, static_cast<int>((centre[id][axis] - lo) * scale)) <= split_bin;
    });
    mid = static_cast<int>(part - ids);
  }
  if (mid <= task.begin || mid >= task.end) {
    // Median split on the longest centroid extent (or by position in the
    // array when every centroid coincides).
    int a = 0;
    if (extent.y > extent[a]) a = 1;
    if (extent.z > extent[a]) a = 2;
    mid = task.begin + n / 2;
    std::nth_element(ids + task.begin, ids + mid, ids + task.end,
                     [&](int i, int j) { return centre[i][a] < centre[j][a]; });
  }
  const int left = static_cast<int>(nodes.size());
  nodes.emplace_back();
  nodes.emplace_back();
  nodes[task.node].first = left;
  nodes[task.node].count = 0;
  tasks.push_back({left + 1, mid, task.end, task.depth + 1});
  tasks.push_back({left, task.begin, mid, task.depth + 1});
}

}  // namespace

void AabbTree::build(const std::vector<BBox>& boxes) {
  nodes_.clear();
  ids_.clear();
  depth_ = 0;
  // Centres as plain arrays: the binning indexes their axes at run time.
  std::vector<std::array<double, 3>> centre(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (boxes[i].empty()) continue;
    ids_.push_back(static_cast<int>(i));
    const Vec3 c = boxes[i].center();
    centre[i] = {c.x, c.y, c.z};
  }
  if (ids_.empty()) return;
  nodes_.reserve(2 * ids_.size());
  nodes_.emplace_back();
  // The root's split here; its two subtrees (disjoint ranges of ids_) on
  // two threads: the left one into nodes_ as a serial build would, the
  // right one into an array of its own, appended after with its nodes' first
  // child moved by the offset: the same tree on any number of threads, nodes
  // in the same order.
  std::vector<Task> root_tasks;
  split_task({0, 0, static_cast<int>(ids_.size()), 1}, boxes, centre, ids_.data(), nodes_, root_tasks, depth_);
  if (root_tasks.empty()) return;  // the root is a leaf
  const Task left_top = root_tasks[1], right_top = root_tasks[0];  // pushed right, then left
  std::vector<Node> right;
  int right_depth = 0;
  auto build_from = [&](Task top, std::vector<Node>& nodes, int& depth) {
    std::vector<Task> tasks{top};
    while (!tasks.empty()) {
      const Task task = tasks.back();
      tasks.pop_back();
      split_task(task, boxes, centre, ids_.data(), nodes, tasks, depth);
    }
  };
  run_chunks(2, ids_.size() >= kParallelBuild && available_threads() > 1 ? 2 : 1, [&](int, int begin, int end) {
    for (int side = begin; side < end; ++side) {
      if (side == 0) {
        build_from(left_top, nodes_, depth_);  // into the capacity reserved: no reallocation
      } else {
        right.reserve(2 * static_cast<std::size_t>(right_top.end - right_top.begin));
        right.emplace_back();
        build_from({0, right_top.begin, right_top.end, right_top.depth}, right, right_depth);
      }
    }
  });
  // The right subtree's local node i >= 1 goes to offset + i - 1, its root to right_top.node.
  const int offset = static_cast<int>(nodes_.size());
  auto relocated = [&](Node n) {
    if (!n.is_leaf()) n.first = offset + n.first - 1;
    return n;
  };
  nodes_[static_cast<std::size_t>(right_top.node)] = relocated(right[0]);
  for (std::size_t i = 1; i < right.size(); ++i) nodes_.push_back(relocated(right[i]));
  depth_ = std::max(depth_, right_depth);
  // Reserved for the worst case (2 per primitive): the capacity never
  // written is address space, not memory, and a tight copy would briefly
  // hold the nodes twice.
}

}  // namespace anisurf
