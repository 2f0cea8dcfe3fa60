// The two fixed meshes of the report's section 6 seen from the mesh being
// adapted (T_1):
//  - T_G, the geometry: every new or moved vertex of T_1 is projected onto
//    it (GeometrySurface: the polyhedral mesh itself, or the G1 Bezier
//    surface of section 3 evaluated at the polyhedral projection's
//    parameters);
//  - T_0, the control space: the metric (and an optional solution) given at
//    its vertices, interpolated at the location of a T_1 vertex in T_0
//    (ControlSpace), never from the moving mesh.
// Both keep one search structure each (section 4) and answer from hints.
#pragma once
#include <array>
#include <atomic>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "geometry/bezier_surface.h"
#include "locate/locator.h"
#include "metric/length.h"
#include "metric/metric_field.h"

namespace anisurf::remesh {

// A point projected onto the geometry: the point on the surface, its
// location on the polyhedral T_G (triangle, barycentric coordinates: the
// hint of the next search) and the unit surface normal there.
struct Projection {
  Vec3 point;
  Location location;
  Vec3 normal;
};

// The surface T_1 is kept on. One implementation change swaps the polyhedral
// surface for the G1 one.
class GeometrySurface {
 public:
  virtual ~GeometrySurface() = default;
  // Closest point of the surface to x under the constraint (section 4.2),
  // searched from the hints. Not const: searches use scratch marks.
  virtual Projection project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) = 0;
  // The closest point of T_G's triangles to x, searched from the hints (the
  // smooth surface is not evaluated): what a distance to the input measures.
  Location closest_on_input(const Vec3& x, std::span<const Hint> hints) {
    return locator().project(x, hints, Constraint::Free);
  }
  // Whether T_G's triangles come within tol of x (Locator::within).
  bool input_within(const Vec3& x, double tol, std::span<const Hint> hints) {
    return locator().within(x, tol, hints);
  }
  // A location of T_G's triangles within tol of x, else the closest
  // (Locator::first_within).
  Location first_on_input_within(const Vec3& x, double tol, std::span<const Hint> hints) {
    return locator().first_within(x, tol, hints);
  }
  // Whether a free projection's point is the closest point of T_G's
  // triangles (the surface is T_G itself).
  virtual bool projects_onto_input() const { return false; }
  // A bound of the distance from the surface point at a location on triangle
  // t of T_G (at()) to that location's point on t; infinite where the free
  // projection does not take the surface at the polyhedral location.
  virtual double deviation_bound(Triangle t) = 0;
  // The surface point at a location on T_G (a point of its triangles, as a
  // projection gives), with the unit normal there: a vertex of T_G is its own
  // surface point.
  virtual Projection at(const Location& where) const = 0;
  // The polyhedral mesh T_G (tags: features, corners).
  virtual const SurfaceMesh& mesh() const = 0;
  virtual std::string name() const = 0;
  // Distance from vertex v of T_G to the nearest triangle not incident to
  // it (Locator::clearance): small where another sheet of the surface comes
  // close (a thin part, a defective input).
  virtual double clearance(Vertex v) const = 0;
  // A surface for another thread: it shares this one's immutable data
  // (patches, search trees) and has its own search marks. Pre: this one
  // outlives the copy.
  virtual std::unique_ptr<GeometrySurface> copy_for_thread() const = 0;

 protected:
  virtual Locator& locator() = 0;
};

// T_G as it is: projection onto the triangles (locate/locator.h).
class PolyhedralSurface final : public GeometrySurface {
 public:
  // Pre: `mesh` has its features tagged and outlives the surface.
  explicit PolyhedralSurface(const SurfaceMesh& mesh);
  // With the locator of that mesh already built.
  explicit PolyhedralSurface(Locator locator);
  Projection project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) override;
  Projection at(const Location& where) const override;
  const SurfaceMesh& mesh() const override { return locator_.mesh(); }
  std::string name() const override { return "polyhedral"; }
  bool projects_onto_input() const override { return true; }
  double deviation_bound(Triangle) override { return 0; }
  double clearance(Vertex v) const override { return locator_.clearance(v); }
  std::unique_ptr<GeometrySurface> copy_for_thread() const override {
    return std::make_unique<PolyhedralSurface>(*this);
  }

 private:
  Locator& locator() override { return locator_; }
  Locator locator_;
};

// The G1 Bezier surface over T_G (geometry/bezier_surface.h, report section
// 3). Two ways to put a point on it:
//  Parametric: x is located on the polyhedral T_G, then the patch of that
//    triangle is evaluated at the same barycentric coordinates (the
//    report's "Farin's algorithm together with a projection algorithm");
//  Closest: the closest point of the surface, by Gauss-Newton on the
//    parameters from there (locate/surface_projection.h), about 5x slower
//    and, on the bench cases, no closer to the exact surfaces.
class BezierGeometry final : public GeometrySurface {
 public:
  enum class Mode { Parametric, Closest };
  // Pre: `mesh` has its features tagged and outlives the surface.
  explicit BezierGeometry(const SurfaceMesh& mesh, Mode mode = Mode::Parametric);
  // With the locator of `mesh` already built.
  BezierGeometry(const SurfaceMesh& mesh, Mode mode, Locator locator);
  // With the patches of the locator's mesh already built (section 3).
  BezierGeometry(std::shared_ptr<const BezierSurface> surface, Mode mode, Locator locator);
  Projection project(const Vec3& x, std::span<const Hint> hints, Constraint constraint) override;
  Projection at(const Location& where) const override;
  const SurfaceMesh& mesh() const override { return locator_.mesh(); }
  std::string name() const override { return "g1-bezier"; }
  // Parametric: BezierSurface::flat_deviation, found on first use.
  double deviation_bound(Triangle t) override;
  double clearance(Vertex v) const override { return locator_.clearance(v); }
  std::unique_ptr<GeometrySurface> copy_for_thread() const override {
    return std::unique_ptr<GeometrySurface>(new BezierGeometry(*this));
  }

 private:
  BezierGeometry(const BezierGeometry&) = default;  // shares the patches, copies the locator (own marks)
  Locator& locator() override { return locator_; }
  // The surface at a point of triangle t, from the patch cache.
  SurfacePoint evaluate(Triangle t, const Bary& b);
  // Shared with the copies for other threads.
  std::shared_ptr<const BezierSurface> surface_;
  Locator locator_;
  Mode mode_;
  // deviation_bound per triangle slot of T_G, shared with the copies (0: not
  // found yet; the bound rounded up to a float, positive).
  std::shared_ptr<std::vector<std::atomic<float>>> deviation_;
  // The control points of the triangles projected onto last (each thread's
  // copy its own): the operators' checks project many points near the same
  // few triangles of T_G, and a patch is assembled from its shared parts.
  // Direct-mapped by triangle id; a slot holds its triangle's id + 1 (0: empty).
  static constexpr int kCachedPatches = 64;
  std::array<int, kCachedPatches> cached_id_plus_one_{};
  std::array<BezierSurface::Patch, kCachedPatches> cached_patch_{};
};

// What T_0 gives at a point of T_1: the metric and the solution values.
struct ControlValues {
  SymTensor3 metric;
  std::vector<FieldValue> fields;  // one per ControlSpace::field_infos()
};

// T_0: a mesh with one metric per vertex slot and optional solution fields
// (every field of the mesh whose name differs from `metric_field_name`).
class ControlSpace {
 public:
  // `same_as_geometry`: T_0 is the very mesh of T_G, so the location found on
  // T_G is the location on T_0 (no second search). Pre: one SPD metric per
  // vertex slot of `mesh`; the mesh outlives the control space.
  // `complexity`: metric_complexity(mesh, metric) when the caller has it
  // (NaN: computed here).
  ControlSpace(const SurfaceMesh& mesh, MetricField metric, bool same_as_geometry,
               MetricInterpolation interpolation = MetricInterpolation::Linear,
               const std::string& metric_field_name = "metric",
               double complexity = std::numeric_limits<double>::quiet_NaN());

  // Location of x in T_0, from a hint; `on_geometry` is x's location on T_G,
  // used as is when T_0 is T_G.
  Location locate(const Vec3& x, Hint hint, const Location& on_geometry);
  // True when T_0 is T_G: locate() then searches nothing (and may be called
  // from several threads).
  bool is_geometry() const { return !locator_; }
  // Metric and solution interpolated at a location of T_0.
  ControlValues values_at(const Location& where) const;
  SymTensor3 metric_at(const Location& where) const;

  const SurfaceMesh& mesh() const { return mesh_; }
  // The metric in use (the target, or a relaxed one: set_relaxation) and
  // the target at T_0's vertex slots, rebuilt from the stored form.
  MetricField metric() const;
  MetricField target_metric() const;
  // metric_complexity of the target on T_0, without a copy of the field;
  // computed once for this space and its copies (every Remesher, one a
  // region, asks for it).
  double target_complexity() const;

  // True when the metric in use is isotropic (eq. 3) at every vertex of T_0,
  // to 1e-12 (metric.h is_isotropic): so is then every metric interpolated
  // from it (a weighted sum of multiples of I).
  bool is_isotropic() const;

  // Remark 6: the metric in use becomes the log-Euclidean interpolation
  // exp((1 - t) log M_0 + t log M) between the metric M_0 the mesh T_0
  // already satisfies (isotropic, the mean length of the edges at each
  // vertex) and the target M; t = 1 restores the target.
  void set_relaxation(double t);
  const std::vector<FieldInfo>& field_infos() const { return infos_; }
  bool same_as_geometry() const { return !locator_; }
  // A control space for another thread: it shares the target metric and
  // T_0, and has its own locator marks and relaxed metric. Pre: this one
  // outlives the copy.
  std::unique_ptr<ControlSpace> copy_for_thread() const;

 private:
  ControlSpace(const ControlSpace& other);
  const SurfaceMesh& mesh_;
  // T_0's metrics are stored once, in the space where `interpolation_` is
  // linear (metric/length.h: M, M^-1, M^-1/2 or log M): a lookup is then one
  // weighted sum and one conversion back.
  const MetricField& in_use() const { return relaxed_.empty() ? *target_ : relaxed_; }
  MetricInterpolation interpolation_;
  std::shared_ptr<const MetricField> target_;  // shared with the copies for other threads
  double complexity_ = 0;  // of target_ (computed before its conversion to the interpolation space)
  MetricField relaxed_;  // the metric in use while relaxed (empty otherwise: the target, not copied)
  MetricField implied_;  // M_0 of set_relaxation (a metric), computed on first use
  std::unique_ptr<Locator> locator_;  // null when T_0 is T_G
  std::vector<FieldInfo> infos_;
  std::vector<Property<FieldValue>> fields_;
};

}  // namespace anisurf::remesh
