// The adaptation of the editor: the remesher of engine/remesh driven pass by
// pass in a worker thread (Remesher::advance(): run()'s schedule, relaxation
// stages included), with a snapshot of the mesh and of the schedule after
// every pass (the timeline the Adaptation panel scrubs), so that a run can
// pause after any pass, resume, or restart from any snapshot.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "editor/analysis.h"
#include "mesh/surface_mesh.h"
#include "metric/metric_field.h"
#include "remesh/adapt.h"

namespace anisurf::editor {

// The options of the engine's pipeline (remesh/adapt.h): the same defaults
// as `anisurf adapt` (lmin 0.72, the size read linearly in T_0, the G1
// surface). The metric recipe is the session's.
using AdaptSettings = remesh::AdaptOptions;

using remesh::Schedule;

// One state of the timeline: the mesh (T_1, with the engine's placement of
// every vertex: remesh::kPlacementProperty), the metric per vertex slot, the
// placements counted, the pass that produced it (absent for the initial
// state) and the schedule after it.
struct Snapshot {
  SurfaceMesh mesh;
  MetricField metric;
  PlacementCounts placement;  // count_placements(mesh); not known for the initial state
  bool has_report = false;
  remesh::PassReport report;
  Schedule schedule;
  std::string label;  // "initial", "3 split" ...
};

// The vertex properties the remesher keeps for its own work (the metric,
// normals, location hints: AdaptedMesh rebuilds them from a snapshot's mesh);
// a snapshot's mesh goes without them (68 bytes per vertex slot), keeping
// the placements (remesh::kPlacementProperty) and the solution fields.
inline constexpr const char* kRemesherWorkingProperties[] = {remesh::kMetricProperty, remesh::kIsotropicMetricProperty,
                                                              "remesh:normal", "remesh:hint_g", "remesh:hint_0"};
// A copy of the adapted mesh for a snapshot: without the working properties.
SurfaceMesh snapshot_mesh(const SurfaceMesh& adapted);

// A run keeps the snapshots of its last kMaxRunSnapshots passes; older
// passes of the same run leave the timeline (the states before the run stay,
// so a cancel still returns to where it started). A falcon-sized snapshot
// takes about 7 MB.
inline constexpr std::size_t kMaxRunSnapshots = 6;

// The surface T_G over T_0 (G1 or polyhedral as settings say); it does not
// depend on the metric, so a session builds it once per mesh, in the
// background (start_geometry), and every adaptation of that mesh shares it.
using SharedGeometry = std::shared_future<std::shared_ptr<remesh::GeometrySurface>>;
SharedGeometry start_geometry(const SurfaceMesh& input, const AdaptSettings& settings);

class Adaptation {
 public:
  // T_0 = `input` (features tagged; must outlive the adaptation) with
  // `metric`, on `geometry` (built over `input` when t0_is_geometry, else
  // over the mesh T_0 was adapted from: a later cycle). The geometry answers
  // one adaptation at a time: the worker holds `geometry_lock` (the same
  // mutex for every adaptation on that geometry) while it works. The
  // timeline starts with `initial` (T_0's snapshot).
  Adaptation(const SurfaceMesh& input, MetricField metric, const AdaptSettings& settings,
             std::shared_ptr<const Snapshot> initial, SharedGeometry geometry, std::shared_ptr<std::mutex> geometry_lock,
             bool t0_is_geometry = true);
  ~Adaptation();  // stops the worker (after its current pass)
  Adaptation(const Adaptation&) = delete;
  Adaptation& operator=(const Adaptation&) = delete;

  // Sets the remesher up from the initial state in the worker (the control
  // space, the mesh on the geometry: seconds on a large mesh), without a
  // pass, so that start() begins with the pass. No-op if the worker runs or
  // the remesher is set up.
  void prepare();
  // Starts the worker from snapshot `from` (cutting the timeline after it)
  // for at most max_passes passes (0: until the schedule is done); during a
  // prepare() the passes follow it. No-op if passes run or the schedule is
  // done; returns whether passes were started (or queued after the setup).
  bool start(std::size_t from, int max_passes);
  void request_stop() { stop_ = true; }
  void wait();
  // Passes run or are about to (not a prepare() alone).
  bool running() const { return passes_; }
  // The surface the passes ran on (null before the first pass).
  std::shared_ptr<remesh::GeometrySurface> geometry() const { return geometry_; }
  // The worker is alive (passes or a prepare()).
  bool working() const { return running_; }
  // Drops the snapshots after `keep` (worker idle).
  void truncate(std::size_t keep);
  // Passes that left the timeline under kMaxRunSnapshots since the start.
  std::size_t dropped_passes() const { return dropped_passes_; }

  std::vector<std::shared_ptr<const Snapshot>> timeline() const;
  std::size_t size() const;
  std::uint64_t version() const { return version_; }
  std::string error() const;
  // Seconds of the last pass and the time to take its snapshot.
  double last_pass_seconds() const { return last_pass_seconds_; }
  double last_snapshot_seconds() const { return last_snapshot_seconds_; }
  // Seconds from start() to the beginning of its first pass (the remesher's
  // setup, or what was left of a prepare(); about 0 when it resumed from
  // where it stopped).
  double last_setup_seconds() const { return last_setup_seconds_; }

 private:
  // The worker: prepare_only sets the remesher up, then runs the passes a
  // start() queued meanwhile, if any.
  void work(std::size_t from, int max_passes, bool prepare_only);
  void rebuild_from(const Snapshot& s);
  // Under mutex_: keeps the last kMaxRunSnapshots passes of the run that
  // started from snapshot `from`.
  void drop_oldest_passes_of_run(std::size_t from);

  const SurfaceMesh& input_;
  bool t0_is_geometry_;
  AdaptSettings settings_;
  SharedGeometry geometry_future_;
  std::shared_ptr<std::mutex> geometry_lock_;
  std::shared_ptr<remesh::GeometrySurface> geometry_;
  std::unique_ptr<remesh::ControlSpace> control_;
  std::unique_ptr<remesh::AdaptedMesh> adapted_;
  std::unique_ptr<remesh::Remesher> remesher_;
  MetricField metric_;
  std::size_t built_from_ = static_cast<std::size_t>(-1);  // timeline index the remesher state is at

  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const Snapshot>> timeline_;
  std::string error_;
  std::thread worker_;
  std::atomic<bool> stop_{false}, running_{false}, passes_{false};
  bool preparing_ = false;  // under mutex_, as queued_
  struct Queued {
    std::size_t from;
    int max_passes;
  };
  std::optional<Queued> queued_;
  std::chrono::steady_clock::time_point start_requested_;
  std::atomic<std::uint64_t> version_{1};
  std::atomic<std::size_t> dropped_passes_{0};
  std::atomic<double> last_pass_seconds_{0}, last_snapshot_seconds_{0}, last_setup_seconds_{0};
};

}  // namespace anisurf::editor
