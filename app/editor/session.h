// The editor's data (no OpenGL, no ImGui): the input mesh T_0 with its
// features, the metric settings and the metric field they give, painted
// edits with undo / redo, the adaptation (adaptation.h) with its timeline of
// snapshots, the analysis of the displayed state, its distance to the input
// surface T_G (measured in the background) and the selection. Panels
// and scripts change the session only through these calls; each call that
// changes the session appends the equivalent script line to journal() (the
// autosave replays it).
#pragma once
#include <chrono>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/adaptation.h"
#include "editor/analysis.h"
#include "geometry/features.h"
#include "locate/surface_distance.h"
#include "mesh/surface_mesh.h"
#include "metric/metric_field.h"
#include "metric/recipe.h"

namespace anisurf::editor {

struct MetricSettings {
  enum class Source { Iso, Size, Hessian, Curvature, Sol };
  Source source = Source::Iso;
  double iso = 0.1;                      // metric iso H
  std::string size_expr = "0.05 + 0.1 * abs(y)";  // metric size EXPR
  std::string hessian_expr = "x * x";    // metric hessian EXPR ERR
  double hessian_error = 0.01;
  double hausd = 0.01;                   // metric curvature HAUSD
  std::string sol_path;                  // metric sol FILE
  double hgrad = 1.3;                    // gradation ratio (<= 1: off)
  double hausd_bound = 0;                // chordal deviation bound (Mmg's -hausd; 0: none)
  double hmin = 0.0;
  double hmax = std::numeric_limits<double>::infinity();
  double max_aniso = std::numeric_limits<double>::infinity();
  bool operator==(const MetricSettings&) const = default;
};
const char* source_name(MetricSettings::Source s);
// `path` made absolute (and normal: no "." or ".." parts).
std::string absolute_path(const std::string& path);
// Where the editor saves by default: beside the opened file, with its name
// ("dir/bunny.off" -> "dir/bunny.adapted.mesh", "dir/bunny.adapted.sol"),
// absolute.
std::string default_save_mesh(const std::string& opened);
std::string default_save_sol(const std::string& opened);
// The script line that selects the source of `s` ("metric iso 0.1").
std::string source_line(const MetricSettings& s);

// The metric brush (section "metric painting" of the editor).
struct Brush {
  enum class Mode { Set, Smooth, Erase };
  enum class Direction { Stroke, MaxCurvature, MinCurvature };
  Mode mode = Mode::Set;
  Direction direction = Direction::Stroke;
  double radius = 0.2;    // world units
  double size = 0.05;     // target size across the stretch direction
  double stretch = 1.0;   // >= 1: size along the direction = size * stretch
  double strength = 1.0;  // blend weight at the centre, in (0, 1]
};

// One undoable change of the metric: the vertices and their values before
// and after (restored exactly), and the settings before and after.
struct MetricEdit {
  std::string what;
  std::vector<int> vertices;
  std::vector<SymTensor3> before, after;
  MetricSettings settings_before, settings_after;
  // A change of settings: the settings' fields before and after (undo and
  // redo restore them without building them again).
  std::shared_ptr<const MetricField> base_before, base_after;
};

// Where the adaptation stands, for the status bar:
//   Idle        no pass since the mesh, the metric or the band last changed;
//   Running     passes run;
//   Pausing     a pause was asked: the pass in progress ends, then it stops;
//   Cancelling  a cancel was asked: the pass in progress ends, then the run is dropped;
//   Paused      stopped by Pause or after the passes asked for (Step, run N);
//               Run / Step go on from there;
//   Converged   the schedule ended: the last round changed (almost) nothing;
//   Cancelled   the last run was dropped: the timeline is back where it started;
//   Failed      the last pass failed (adaptation_error() says why).
enum class RunState { Idle, Running, Pausing, Cancelling, Paused, Converged, Cancelled, Failed };
// "idle", "running", "pausing", ...
const char* run_state_name(RunState s);

// What the view shows: the mesh, its metric and the pass that produced it.
struct DisplayState {
  std::shared_ptr<const Snapshot> snapshot;  // T_0 with the current metric, or a pass
  std::uint64_t version = 0;                 // changes whenever the state shown changes
};

class EditorSession {
 public:
  EditorSession();
  ~EditorSession();

  // --- file -----------------------------------------------------------------
  // Loads T_0 and its features: a file that lists features (Medit's Ridges,
  // Corners, RequiredEdges, as save() writes them) keeps them as given (no
  // ridge detection; corners added only where a feature curve ends or
  // branches), else they are detected as `anisurf adapt` does. The metric
  // comes from SOL when given (or from the file's own metric field): source
  // Sol, used as given (gradation off, no bounds; the user may set them
  // afterwards); else the current settings, an iso size taken from the
  // input's density (the metric predicts as many vertices as it has). The
  // brush radius becomes a tenth of the diagonal, its size half that
  // density. Clears the undo stack and the adaptation. Throws Error with
  // the file's message.
  void open(const std::string& mesh_path, const std::string& sol_path = {});
  bool has_mesh() const { return input_ != nullptr; }
  const std::string& mesh_path() const { return mesh_path_; }
  // Counts the meshes opened (a new one invalidates what views kept).
  int opened() const { return opened_; }
  const SurfaceMesh& input() const { return *input_; }
  // How T_0's features were obtained at open(), and their counts.
  bool features_from_file() const { return features_from_file_; }
  const FeatureReport& features() const { return features_; }
  // Writes the displayed mesh (with its features: Ridges, Corners,
  // RequiredEdges in a .mesh) and (if sol_path is not empty) its metric.
  void save(const std::string& mesh_path, const std::string& sol_path = {});
  // The files among mesh_path, sol_path (empty ones skipped) that exist and
  // that this session did not write since the mesh was opened: what a save
  // would overwrite and should ask about first.
  std::vector<std::string> would_overwrite(const std::string& mesh_path, const std::string& sol_path = {}) const;
  // True when the metric or the mesh changed since open / save.
  bool dirty() const { return dirty_; }

  // --- metric ---------------------------------------------------------------
  const MetricSettings& settings() const { return settings_; }
  // Recomputes the metric from `s` (undoable); resets the adaptation. Throws
  // Error (bad expression, unreadable .sol ...) leaving the session unchanged.
  void set_settings(const MetricSettings& s);
  const MetricField& metric() const { return metric_; }
  // The metric before painting (the settings' field), for the erase mode.
  const MetricField& base_metric() const { return base_metric_; }
  // Vertices the metric predicts (report section 2.2), of the current field.
  double predicted_vertices() const { return predicted_vertices_; }
  // The same for settings `s` without applying them (throws like set_settings).
  double predict_vertices(const MetricSettings& s) const;

  // --- the metric built in the background -------------------------------------
  // A metric can take seconds to build (a curvature metric of a 75k-triangle
  // mesh): the panel asks for it here and the window keeps drawing the
  // current one meanwhile. The metric of `s` is built in a thread of its own,
  // one build at a time. apply: once built it is installed as set_settings()
  // installs it (undoable, journalled), by poll(); else only kept for
  // preview() (the panel's predicted vertex count). A newer request of the
  // same kind supersedes the older one: a waiting request is replaced, a
  // build in progress runs to its end (the engine cannot stop it) and its
  // result is then only kept for preview(), never installed. The last
  // metric built is kept: applying the settings just previewed installs it
  // at once. Settings equal to the current ones cancel a waiting apply.
  // Throws Error without a mesh.
  void request_metric(const MetricSettings& s, bool apply);
  // A build runs or waits; the settings it builds and for how long it has
  // run (seconds), and whether it will be installed.
  bool metric_building() const { return metric_job_.valid() || pending_apply_ || pending_preview_; }
  const MetricSettings& metric_build_of() const { return metric_job_of_; }
  double metric_build_seconds() const;
  bool metric_build_applies() const { return pending_apply_.has_value() || (metric_job_.valid() && metric_job_apply_); }
  // The predicted vertices of `s` once its metric is built (the last build).
  std::optional<double> preview(const MetricSettings& s) const;
  // Why the build of `s` failed (empty: it did not fail, or was not asked).
  std::string metric_error(const MetricSettings& s) const;
  // The last failed build that was to be installed ("" after a success or a
  // new apply request): a script stops on it.
  const std::string& apply_error() const { return apply_error_; }
  // Seconds the last finished build took.
  double last_metric_seconds() const { return last_metric_seconds_; }

  // --- painting -------------------------------------------------------------
  Brush& brush() { return brush_; }
  // A stroke is one undoable edit: begin, dabs, end. A dab outside a stroke
  // is a stroke of its own. `direction`: the stroke direction (world), used
  // when brush().direction == Stroke and stretch > 1.
  void begin_stroke();
  void dab(const Vec3& centre, const Vec3& direction = {});
  void end_stroke();
  bool in_stroke() const { return stroke_.has_value(); }

  bool can_undo() const { return !undo_.empty() && !stroke_; }
  bool can_redo() const { return !redo_.empty() && !stroke_; }
  std::string undo_label() const { return undo_.empty() ? "" : undo_.back().what; }
  std::string redo_label() const { return redo_.empty() ? "" : redo_.back().what; }
  bool undo();
  bool redo();

  // --- adaptation -----------------------------------------------------------
  const AdaptSettings& adapt_settings() const { return adapt_settings_; }
  // The edge length band of the next adaptation (0 < lmin < lmax); drops
  // the current one. Throws Error on a bad band.
  void set_band(double lmin, double lmax);
  // One pass / passes until converged (at most max_passes, 0: no limit), in
  // the worker thread from the displayed snapshot (a scrubbed timeline is cut
  // after it). wait(): block until the worker is idle.
  void step();
  void run(int max_passes = 0);
  void pause();   // stop after the current pass
  // When the pause (or cancel) of the run in progress was asked (nullopt:
  // none since the run started): the window measures how long stopping took.
  std::optional<std::chrono::steady_clock::time_point> stop_requested() const { return stop_requested_; }
  void cancel();  // stop and go back to where the current run started (once the pass in progress ends)
  // Applies what waited for the worker to be idle (a cancel), installs a
  // metric built in the background, and once the session has been still for
  // kPrepareDelay sets the next adaptation's remesher up in the background
  // (Adaptation::prepare(): Step then begins with its pass); call every frame.
  void poll();
  static constexpr std::chrono::milliseconds kPrepareDelay{500};
  void reset();   // back to T_0 (the timeline is dropped)
  // Section 7.1's adaptation cycle: the displayed mesh (worker idle) becomes
  // T_0, its metric derived again from the settings (a Hessian, size or
  // curvature source is evaluated on it; a .sol or a painted metric is
  // carried: the displayed snapshot's). T_G stays the opened mesh's surface.
  // Clears the undo stack; returns the new T_0's vertex count. Throws Error
  // (no adapted mesh shown, a metric that cannot be built) leaving the
  // session unchanged.
  int next_cycle();
  // Cycles done since open (0: T_0 is the opened mesh).
  int cycle() const { return cycle_; }
  void wait();
  bool running() const;
  // Runs (Step or Run) started since the session was made: the window tells
  // a run that began and ended within one frame from no run at all.
  std::size_t runs_started() const { return runs_started_; }
  RunState run_state() const;
  std::vector<std::shared_ptr<const Snapshot>> timeline() const;
  // Shows pass `index` of the timeline (-1: follow the latest).
  void scrub(int index);
  int scrubbed() const { return scrub_; }
  std::string adaptation_error() const;
  // The current adaptation's timings (adaptation.h), 0 without one.
  double last_setup_seconds() const { return adaptation_ ? adaptation_->last_setup_seconds() : 0; }
  double last_snapshot_seconds() const { return adaptation_ ? adaptation_->last_snapshot_seconds() : 0; }
  // Passes that left the timeline (Adaptation::dropped_passes()).
  std::size_t dropped_passes() const { return adaptation_ ? adaptation_->dropped_passes() : 0; }

  // --- display, analysis, selection -----------------------------------------
  DisplayState display() const;
  // Analysis of the displayed state (cached per state; waits for it).
  const Analysis& analysis();
  // Without waiting (the panel): the last analysis made, of the displayed
  // state or of an earlier one (null before the first); the displayed
  // state's is made in a thread of its own meanwhile. analysis_current():
  // the last one made is the displayed state's.
  const Analysis* latest_analysis();
  bool analysis_current() const { return analysis_of_ && analysis_of_ == display().snapshot; }
  // Selects the elements of a histogram bin (kind "length" or "quality");
  // throws Error for a bin out of range. Empty selection: clear.
  void select_bin(BinKind kind, int bin);
  void clear_selection();
  const Selection& selection() const { return selection_; }

  // --- distance to the input ------------------------------------------------
  // T_G: the surface every adaptation stays on (the opened mesh, also after
  // cycles).
  const SurfaceMesh& geometry_input() const { return geometry_mesh_ ? *geometry_mesh_ : *input_; }
  // The chordal deviation the metric of `s` runs with: its curvature's, its
  // hausd bound, or for a Hessian the geometry protection of `anisurf adapt`
  // (remesh::effective_hausd with T_G's diagonal; a loaded metric is used as
  // given), or 0.
  double effective_hausd(const MetricSettings& s) const;
  // The distance from a state of the timeline to T_G (vertices, edge
  // midpoints, centroids: locate/surface_distance.h) is measured in a thread
  // of its own, one state at a time, so that the view stays responsive; the
  // first measure after open() also builds the locator over T_G.
  //
  // Starts measuring `state` unless it is the last state measured or the one
  // being measured; while another one is measured, it waits (only the latest
  // request waits).
  void request_distance(const std::shared_ptr<const Snapshot>& state);
  // The distance of `state` once measured (null before, or if not asked for).
  std::shared_ptr<const SurfaceDistance> ready_distance(const std::shared_ptr<const Snapshot>& state);
  // request_distance() and wait: the distance of `state` / of the displayed
  // state. Throws Error when the measure failed; null without a mesh.
  std::shared_ptr<const SurfaceDistance> distance(const std::shared_ptr<const Snapshot>& state);
  std::shared_ptr<const SurfaceDistance> distance();
  // The last state measured and its distance (null if none since open());
  // `of_displayed`: it is the displayed state. They do not wait.
  std::shared_ptr<const Snapshot> last_measured() const { return distance_of_; }
  std::shared_ptr<const SurfaceDistance> last_distance(bool* of_displayed = nullptr) const;
  // A measure runs or waits.
  bool measuring() const { return distance_job_.valid() || distance_pending_ != nullptr; }
  // Seconds the last measure took (the locator's build included when it was
  // built then), and why the last one failed ("" if it did not).
  double last_distance_seconds() const { return distance_seconds_; }
  const std::string& distance_error() const { return distance_error_; }

  // --- journal --------------------------------------------------------------
  // Script lines equivalent to what was done (for the autosave).
  const std::vector<std::string>& journal() const { return journal_; }
  void log(const std::string& line);
  std::uint64_t version() const { return version_; }

 private:
  void apply_metric(MetricField m, const MetricSettings& s, bool reset_adaptation);
  // set_settings() once the metric of `s` is built.
  void install_settings(const MetricSettings& s, MetricField m);
  // The background builds: start one, collect a finished one (installing it
  // when asked), and wait for the one in progress and drop everything (a new
  // T_0: what was built belongs to the old one).
  void start_metric_job(const MetricSettings& s, bool apply);
  void poll_metric();
  void forget_metric_jobs();
  // A metric edit, a reset or a new mesh drops the adaptation without waiting
  // for the pass in progress: it is stopped and kept until its worker ends.
  void retire_adaptation();
  void wait_retired();
  void open_stroke();   // begin_stroke / end_stroke without the journal lines
  void close_stroke();
  void changed();
  // A new adaptation of T_0 with the current metric and settings.
  std::unique_ptr<Adaptation> make_adaptation() const;
  // A new T_0 (open, next_cycle): what was computed or edited on the old
  // one goes (cached normals and curvatures, undo and redo, the selection).
  void forget_input_state();
  // A new T_G (open): the measure in progress ends, the locator and the
  // results go.
  void forget_distance();
  // Collects a finished measure and starts the one waiting.
  void poll_distance();
  void start_distance(std::shared_ptr<const Snapshot> state);
  // The engine's metric recipe of the settings (`loaded`: the metric of a
  // Sol source already read, else the file is read).
  MetricRecipe metric_recipe(const MetricSettings& s, MetricField loaded = {}) const;
  MetricField compute_metric(const MetricSettings& s) const;
  const std::vector<Vec3>& vertex_normals_cached();
  const std::vector<SymTensor3>& curvature_cached();
  std::shared_ptr<const Snapshot> initial_snapshot() const;

  std::unique_ptr<SurfaceMesh> input_;
  // T_G when T_0 is a cycle's adapted mesh (null while T_0 is T_G itself);
  // geometry_ is built over it.
  std::unique_ptr<SurfaceMesh> geometry_mesh_;
  int cycle_ = 0;
  bool metric_painted_ = false;  // the metric was painted since the settings computed it
  std::vector<int> vertex_origin_;
  std::string mesh_path_;
  MetricSettings settings_;
  MetricField metric_, base_metric_;
  double predicted_vertices_ = 0;
  Brush brush_;
  std::optional<MetricEdit> stroke_;
  std::vector<int> stroke_index_;  // vertex -> index in stroke_ (-1)
  std::vector<MetricEdit> undo_, redo_;
  AdaptSettings adapt_settings_;
  std::unique_ptr<Adaptation> adaptation_;
  SharedGeometry geometry_;  // T_G over input_, built in the background at open()
  std::shared_ptr<std::mutex> geometry_lock_ = std::make_shared<std::mutex>();  // one adaptation on geometry_ at a time
  std::chrono::steady_clock::time_point changed_at_;  // the last change (the next adaptation is prepared once still)
  std::vector<std::unique_ptr<Adaptation>> retired_;
  std::shared_ptr<const Snapshot> t0_snapshot_;
  int scrub_ = -1;
  std::size_t run_start_ = 0;  // timeline size when the current run started
  bool cancel_pending_ = false;
  bool cancelled_ = false;  // the last run was cancelled (and nothing ran since)
  std::optional<std::chrono::steady_clock::time_point> stop_requested_;
  std::size_t runs_started_ = 0;
  Analysis analysis_;
  std::shared_ptr<const Snapshot> analysis_of_;
  std::future<Analysis> analysis_job_;  // the analysis of analysis_job_of_, in its thread
  std::shared_ptr<const Snapshot> analysis_job_of_;
  void collect_analysis(bool wait);
  std::uint64_t selection_counter_ = 0;
  Selection selection_;
  // A measure's result, as its thread returns it.
  struct Measured {
    std::shared_ptr<const SurfaceDistance> distance;
    double seconds = 0;
    std::string error;
  };
  std::unique_ptr<Locator> distance_locator_;  // over geometry_input(); built and read by the measuring thread
  std::future<Measured> distance_job_;         // the measure in progress (valid while it runs or is uncollected)
  std::shared_ptr<const Snapshot> distance_job_of_, distance_pending_;
  std::shared_ptr<const SurfaceDistance> distance_;  // the last measure and its state
  std::shared_ptr<const Snapshot> distance_of_;
  double distance_seconds_ = 0;
  std::string distance_error_;
  std::vector<Vec3> normals_;
  std::vector<SymTensor3> curvature_;
  // The background metric builds (request_metric()).
  struct Built {
    std::shared_ptr<const MetricField> metric;
    double predicted = 0;
    std::string error;
    double seconds = 0;
  };
  std::future<Built> metric_job_;
  MetricSettings metric_job_of_;
  bool metric_job_apply_ = false;
  std::chrono::steady_clock::time_point metric_job_start_;
  std::optional<MetricSettings> pending_apply_, pending_preview_;
  std::optional<MetricSettings> built_of_;  // the last build that worked, its field and count
  std::shared_ptr<const MetricField> built_;
  double built_predicted_ = 0;
  std::optional<MetricSettings> failed_of_;  // the last build that failed, and why
  std::string failed_error_, apply_error_;
  double last_metric_seconds_ = 0;
  std::vector<std::string> journal_;
  std::vector<std::string> written_;  // absolute paths save() wrote since open()
  bool features_from_file_ = false;
  FeatureReport features_;
  std::string logged_brush_, logged_direction_;  // brush lines in the journal so far
  bool dirty_ = false;
  int opened_ = 0;
  std::uint64_t version_ = 1;
};

}  // namespace anisurf::editor
