#include "editor/adaptation.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>

#include "core/error.h"
#include "metric/surface_metric.h"
#include "remesh/reference.h"

namespace anisurf::editor {

using remesh::PassKind;
using Clock = std::chrono::steady_clock;

SharedGeometry start_geometry(const SurfaceMesh& input, const AdaptSettings& settings) {
  const remesh::SurfaceKind kind = settings.surface;
  return std::async(std::launch::async, [&input, kind]() -> std::shared_ptr<remesh::GeometrySurface> {
           return remesh::make_geometry(input, kind);
         }).share();
}

Adaptation::Adaptation(const SurfaceMesh& input, MetricField metric, const AdaptSettings& settings,
                       std::shared_ptr<const Snapshot> initial, SharedGeometry geometry,
                       std::shared_ptr<std::mutex> geometry_lock, bool t0_is_geometry)
    : input_(input),
      t0_is_geometry_(t0_is_geometry),
      settings_(settings),
      geometry_future_(std::move(geometry)),
      geometry_lock_(std::move(geometry_lock)),
      metric_(std::move(metric)) {
  if (!geometry_lock_) geometry_lock_ = std::make_shared<std::mutex>();
  timeline_.push_back(std::move(initial));
}

Adaptation::~Adaptation() {
  stop_ = true;
  if (worker_.joinable()) worker_.join();
}

void Adaptation::wait() {
  if (worker_.joinable()) worker_.join();
}

SurfaceMesh snapshot_mesh(const SurfaceMesh& adapted) {
  SurfaceMesh copy = adapted;
  for (const char* working : kRemesherWorkingProperties) copy.vertex_properties().remove(working);
  return copy;
}

void Adaptation::drop_oldest_passes_of_run(std::size_t from) {
  while (timeline_.size() > from + 1 + kMaxRunSnapshots) {
    timeline_.erase(timeline_.begin() + static_cast<std::ptrdiff_t>(from + 1));
    ++dropped_passes_;
  }
}

std::vector<std::shared_ptr<const Snapshot>> Adaptation::timeline() const {
  std::lock_guard lock(mutex_);
  return timeline_;
}

std::size_t Adaptation::size() const {
  std::lock_guard lock(mutex_);
  return timeline_.size();
}

std::string Adaptation::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void Adaptation::truncate(std::size_t keep) {
  if (running_) return;
  std::lock_guard lock(mutex_);
  if (keep >= 1 && keep < timeline_.size()) {
    timeline_.resize(keep);
    ++version_;
  }
}

void Adaptation::prepare() {
  if (running_ || remesher_) return;
  if (worker_.joinable()) worker_.join();
  {
    std::lock_guard lock(mutex_);
    preparing_ = true;
    queued_.reset();
  }
  stop_ = false;
  running_ = true;
  worker_ = std::thread([this] { work(0, 0, true); });
}

bool Adaptation::start(std::size_t from, int max_passes) {
  {
    std::lock_guard lock(mutex_);
    if (running_ && preparing_) {  // the passes follow the setup in progress
      if (timeline_[std::min(from, timeline_.size() - 1)]->schedule.phase == Schedule::Phase::Done) return false;
      queued_ = Queued{from, max_passes};
      error_.clear();
      start_requested_ = Clock::now();
      stop_ = false;
      passes_ = true;
      return true;
    }
  }
  if (running_) return false;
  if (worker_.joinable()) worker_.join();
  {
    std::lock_guard lock(mutex_);
    if (from >= timeline_.size()) from = timeline_.size() - 1;
    if (timeline_[from]->schedule.phase == Schedule::Phase::Done) return false;
    error_.clear();
    start_requested_ = Clock::now();
  }
  stop_ = false;
  running_ = true;
  passes_ = true;
  worker_ = std::thread([this, from, max_passes] { work(from, max_passes, false); });
  return true;
}

void Adaptation::rebuild_from(const Snapshot& s) {
  if (!geometry_) {
    // Auto as anisurf adapt resolves it, on T_G's own metric; the surface
    // started in the background (G1) otherwise.
    if (settings_.surface == remesh::SurfaceKind::Auto && t0_is_geometry_ &&
        remesh::resolve_surface(settings_.surface, input_, metric_, settings_.metric.hausd) ==
            remesh::SurfaceKind::Polyhedral)
      geometry_ = remesh::make_geometry(input_, remesh::SurfaceKind::Polyhedral);
    else
      geometry_ = geometry_future_.valid() ? geometry_future_.get() : start_geometry(input_, settings_).get();
    control_ = remesh::make_control(input_, metric_, t0_is_geometry_, settings_);
  }
  remesher_.reset();
  adapted_.reset();
  adapted_ = std::make_unique<remesh::AdaptedMesh>(s.mesh, *geometry_, *control_, settings_.length, false,
                                                   remesh::input_bound_of(settings_));
  remesh::RemeshOptions options = remesh::remesh_options_of(settings_);
  remesh::set_growth_limits(options, settings_.max_growth, predicted_vertices(input_, metric_), input_.n_vertices());
  remesher_ = std::make_unique<remesh::Remesher>(*adapted_, options);
  remesher_->set_schedule(s.schedule);
}

void Adaptation::work(std::size_t from, int max_passes, bool prepare_only) {
  // Below the window's threads (and llvmpipe's): the window keeps drawing
  // while the passes run. Best effort: ignored if refused.
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 5);
  std::unique_lock geometry_lock(*geometry_lock_);  // one adaptation on the geometry at a time
  if (prepare_only) {
    try {
      std::shared_ptr<const Snapshot> initial;
      {
        std::lock_guard lock(mutex_);
        initial = timeline_.front();
      }
      if (!remesher_) rebuild_from(*initial);
      built_from_ = 0;
    } catch (const std::exception&) {
      // Not reported here: the passes set the remesher up again and report it.
      remesher_.reset();
      adapted_.reset();
      built_from_ = static_cast<std::size_t>(-1);
    }
    std::lock_guard lock(mutex_);
    preparing_ = false;
    if (!queued_ || stop_) {
      queued_.reset();
      passes_ = false;
      running_ = false;
      return;
    }
    from = std::min(queued_->from, timeline_.size() - 1);
    max_passes = queued_->max_passes;
    queued_.reset();
  }
  try {
    std::shared_ptr<const Snapshot> start;
    {
      std::lock_guard lock(mutex_);
      if (timeline_.size() > from + 1) {
        timeline_.resize(from + 1);
        ++version_;
      }
      start = timeline_[from];
    }
    if (built_from_ != from || !remesher_) rebuild_from(*start);
    last_setup_seconds_ = std::chrono::duration<double>(Clock::now() - start_requested_).count();
    // A pause ends the pass in progress early (its snapshot is marked
    // interrupted; the schedule resumes with that pass).
    remesher_->set_interrupt([this] { return stop_.load(); });
    for (int done = 0; (max_passes <= 0 || done < max_passes) && !stop_; ++done) {
      if (remesher_->finished()) break;
      remesh::PassReport r = remesher_->advance();
      const PassKind kind = r.kind;
      const auto t0 = Clock::now();
      const SurfaceMesh& m = adapted_->mesh();
      auto snap = std::make_shared<Snapshot>();
      snap->mesh = snapshot_mesh(m);
      snap->metric.resize(static_cast<std::size_t>(m.vertex_capacity()));
      for (int v = 0; v < m.vertex_capacity(); ++v)
        snap->metric[v] = m.is_deleted(Vertex(v)) ? SymTensor3::identity(1.0) : adapted_->metric(Vertex(v));
      snap->placement = count_placements(snap->mesh);
      snap->has_report = true;
      snap->schedule = remesher_->schedule();
      snap->label = (r.round > 0 ? std::to_string(r.round) + " " : std::string()) +
                    std::string(remesh::pass_name(kind)) + (r.interrupted ? " (interrupted)" : "");
      // A metric the surface cannot carry: the pass stopped, the schedule
      // ended; the mesh so far stays on the timeline, the message says why.
      const std::string stopped =
          r.over_limit ? remesh::over_limit_message({r}, remesher_->options(), predicted_vertices(input_, metric_),
                                                    input_.n_vertices(), settings_.max_growth)
                       : std::string();
      snap->report = std::move(r);
      last_pass_seconds_ = snap->report.seconds;
      last_snapshot_seconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
      {
        std::lock_guard lock(mutex_);
        timeline_.push_back(std::move(snap));
        drop_oldest_passes_of_run(from);
        built_from_ = timeline_.size() - 1;
        if (!stopped.empty()) error_ = stopped;
        ++version_;
      }
      if (!stopped.empty()) break;
    }
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    error_ = e.what();
    built_from_ = static_cast<std::size_t>(-1);
    remesher_.reset();
    adapted_.reset();
    ++version_;
  }
  passes_ = false;
  running_ = false;
}

}  // namespace anisurf::editor
