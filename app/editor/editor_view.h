// The editor's rendering side: turns the session's displayed state and the
// view state into render::Scene structures (the mesh with its quantities,
// the touched vertices of the displayed pass, the selection, the G1 surface
// and its control net), rebuilding only what changed, and answers picks.
// The G1 surface is built in a thread of its own (seconds on a large mesh):
// the view shows what it showed before until it is ready.
#pragma once
#include <array>
#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "editor/session.h"
#include "editor/view_state.h"
#include "render/bezier_structure.h"
#include "render/mesh_structure.h"
#include "render/outline.h"
#include "render/pick.h"
#include "render/scene.h"

namespace anisurf::editor {

// What lies under the mouse: the mesh triangle and its closest vertex.
struct HoverInfo {
  int triangle = -1;  // mesh slot
  int vertex = -1;    // mesh slot
  Vec3 point;
};

class EditorView {
 public:
  // The control net is drawn for at most this many patches (the nearest
  // to the point at the view's centre when the surface was built).
  static constexpr int kNetMaxPatches = 150;
  // The G1 surface is sampled with at most this many sub-triangles: k per
  // edge is lowered on a large mesh (k^2 sub-triangles per triangle) so that
  // it draws about as fast as the mesh.
  static constexpr int kBezierMaxTriangles = 160000;
  // The markers of the vertices the shown pass touched: at most this many
  // drawn, spread over the touched region.
  static constexpr std::size_t kMaxTouchedMarkers = 3000;
  static constexpr const char* kTouchedName = "touched by the pass";
  struct MarkerCounts {
    int shown = 0, total = 0;
  };
  // The frame worst view: the element fills about this fraction of the
  // view's height.
  static constexpr float kFrameFill = 0.4f;
  // The samples per edge drawn for `requested` on a mesh of `triangles`.
  static int bezier_samples(int requested, int triangles);
  ~EditorView();
  // Brings `scene` up to date; `aspect`, reserves: for camera fits.
  void update(EditorSession& session, ViewState& view, render::Scene& scene, float aspect, float reserve_left,
              float reserve_right);
  // The displayed mesh element under pixel (x, y) of a width x height view.
  std::optional<HoverInfo> hover(const render::Scene& scene, float x, float y, int width, int height) const;
  const Snapshot* shown() const { return shown_.get(); }
  const std::shared_ptr<const Snapshot>& shown_state() const { return shown_; }
  // The corners of triangles of the shown state (mesh slots; deleted or
  // unknown slots are left out).
  std::vector<render::WorldTriangle> triangle_corners(std::span<const int> slots) const;
  // The touched vertices' markers of the shown pass: drawn / all.
  MarkerCounts touched_markers() const { return touched_counts_; }
  // Sizes the touched vertices' markers for a width x height view: the
  // fewer markers inside the view, the larger (1.5 to 4.5 px), so that
  // they cover a small share of what they mark.
  void size_markers(render::Scene& scene, int width, int height) const;
  // False while the view waits for a measure to show the displayed state (the
  // distance colours: the state is shown with its distance, once measured).
  // Screenshots wait for it.
  bool settled(const EditorSession& session, const ViewState& view) const;
  double last_build_seconds() const { return build_seconds_; }
  // Synchronous: update() waits for the G1 surface it starts (headless
  // pictures); else it is collected by a later update().
  void set_synchronous(bool on) { synchronous_ = on; }
  // The G1 surface is being built (and since how many seconds), or the one
  // shown is not the displayed state's yet.
  bool bezier_building() const { return bezier_job_.valid(); }
  double bezier_build_seconds() const;
  bool bezier_current(const ViewState& view) const;
  // The patches of the control net shown, of how many; the sampling k the
  // shown surface was built with (0: none shown).
  const render::BezierNetInfo& net_info() const { return net_info_; }
  int bezier_k() const { return bezier_ ? bezier_sampled_k_ : 0; }
  // Builds the control net again around the view's centre.
  void recentre_net() { ++net_epoch_; }

 private:
  // The "distance to input" quantity of the shown mesh.
  void add_distance(const SurfaceDistance& d);
  bool has_distance() const;
  // The state to show next and its distance (see update()).
  struct NextState {
    std::shared_ptr<const Snapshot> snapshot;
    std::shared_ptr<const SurfaceDistance> distance;
  };
  NextState next_to_show(EditorSession& session, const ViewState& view, const std::shared_ptr<const Snapshot>& displayed);
  // Starts building the structure of `next` in the background; collects it
  // once built (true: it became the state shown).
  void start_mesh(const ViewState& view, const EditorSession& session, const NextState& next);
  bool collect_mesh();
  struct MeshBuilt {
    render::MeshStructure structure;
    double seconds = 0;
    MarkerCounts touched;
  };
  // Turns the camera to look at triangle `slot` of the shown state along
  // its normal, from its front, and zooms until it spans about kFrameFill
  // of the free part of the view. No-op for a deleted or unknown slot.
  void frame_triangle(int slot, render::Scene& scene, float aspect, float reserve_left, float reserve_right) const;
  std::future<MeshBuilt> mesh_job_;
  std::shared_ptr<const Snapshot> mesh_job_of_;
  int mesh_job_opened_ = -1;
  MetricSettings mesh_job_settings_;
  // Starts building the G1 surface of shown_ (k = view.bezier) in the
  // background; collects it once built (true: bezier_ changed).
  void start_bezier(const ViewState& view, const render::Scene& scene);
  bool collect_bezier(const ViewState& view);

  std::shared_ptr<const Snapshot> shown_;
  std::uint64_t shown_version_ = ~0ull;
  std::uint64_t selection_version_ = ~0ull;
  render::MeshStructure mesh_;
  std::optional<render::SurfaceStructure> bezier_;
  int bezier_k_ = 0, bezier_sampled_k_ = 0;  // k asked for, k drawn
  std::shared_ptr<const Snapshot> bezier_of_;
  int bezier_epoch_ = 0;
  render::BezierNetInfo net_info_;
  // The build in progress: its state, k and net epoch.
  struct BezierBuilt {
    render::SurfaceStructure structure;
    render::BezierNetInfo net;
  };
  std::future<BezierBuilt> bezier_job_;
  std::shared_ptr<const Snapshot> bezier_job_of_;
  int bezier_job_k_ = 0, bezier_job_sampled_k_ = 0, bezier_job_epoch_ = 0, bezier_job_opened_ = -1;
  std::chrono::steady_clock::time_point bezier_job_start_;
  int net_epoch_ = 0;
  bool synchronous_ = false;
  std::string color_;
  double build_seconds_ = 0;
  MarkerCounts touched_counts_;
  int opened_seen_ = 0;         // session.opened() last seen (a new mesh resets the view)
  int shown_opened_ = -1;       // session.opened() when shown_ was taken
  int kept_for_ = -1;           // session.opened() the ranges belong to
  bool kept_initial_ = false;   // the last structure showed the initial state
  MetricSettings kept_settings_;  // and was made with these settings
  // The colour ranges of the last structure built with its data's own
  // ranges (the settings' metric before any painting), and whether the
  // build in progress keeps them.
  std::vector<std::pair<std::string, std::array<float, 2>>> base_ranges_;
  bool mesh_job_keeps_ = false;
  std::uint64_t counter_ = 1000;
  std::chrono::steady_clock::time_point last_rebuild_;  // structure versions (the renderer re-uploads on a change)
};

}  // namespace anisurf::editor
