// The editor's rendering side: turns the session's displayed state and the
// view state into render::Scene structures (the mesh with its quantities,
// the touched vertices of the displayed pass, the selection, the G1 surface
// and its control net), rebuilding only what changed, and answers picks.
#pragma once
#include <chrono>
#include <memory>
#include <optional>

#include "editor/session.h"
#include "editor/view_state.h"
#include "render/mesh_structure.h"
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
  // Brings `scene` up to date; `aspect`, reserves: for camera fits.
  void update(EditorSession& session, ViewState& view, render::Scene& scene, float aspect, float reserve_left,
              float reserve_right);
  // The displayed mesh element under pixel (x, y) of a width x height view.
  std::optional<HoverInfo> hover(const render::Scene& scene, float x, float y, int width, int height) const;
  const Snapshot* shown() const { return shown_.get(); }
  // False while the view waits for a measure to show the displayed state (the
  // distance colours: the state is shown with its distance, once measured).
  // Screenshots wait for it.
  bool settled(const EditorSession& session, const ViewState& view) const;
  double last_build_seconds() const { return build_seconds_; }

 private:
  // `distance`: the shown state's distance to T_G (null: not measured).
  void rebuild_mesh(const ViewState& view, const EditorSession& session, const SurfaceDistance* distance);
  // The "distance to input" quantity of the shown mesh.
  void add_distance(const SurfaceDistance& d);
  bool has_distance() const;
  // The state to show next and its distance (see update()).
  struct NextState {
    std::shared_ptr<const Snapshot> snapshot;
    std::shared_ptr<const SurfaceDistance> distance;
  };
  NextState next_to_show(EditorSession& session, const ViewState& view, const std::shared_ptr<const Snapshot>& displayed);
  void rebuild_bezier(const ViewState& view);

  std::shared_ptr<const Snapshot> shown_;
  std::uint64_t shown_version_ = ~0ull;
  std::uint64_t selection_version_ = ~0ull;
  render::MeshStructure mesh_;
  std::optional<render::SurfaceStructure> bezier_;
  int bezier_k_ = 0;
  const Snapshot* bezier_of_ = nullptr;
  std::string color_;
  double build_seconds_ = 0;
  int opened_seen_ = 0;         // session.opened() last seen (a new mesh resets the view)
  int shown_opened_ = -1;       // session.opened() when shown_ was taken
  int kept_for_ = -1;           // session.opened() the ranges belong to
  bool kept_initial_ = false;   // the last structure showed the initial state
  MetricSettings kept_settings_;  // and was made with these settings
  std::uint64_t counter_ = 1000;
  std::chrono::steady_clock::time_point last_rebuild_;  // structure versions (the renderer re-uploads on a change)
};

}  // namespace anisurf::editor
