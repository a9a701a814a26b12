#include "workspace_proximity/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "workspace_proximity/upright_box_distance.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// GJK stops once its upper and lower distance bounds agree to this relative tolerance. FCL's
// default (1e-6) leaves cylinder and capsule distances up to ~0.2 % off (up to ~4 % with
// libccd); 1e-9 brings them to ~1e-6 relative at almost no extra cost.
constexpr double kGjkTolerance = 1e-9;

// A GJK answer is accepted when the separating-axis lower bound along its own normal is
// within this of the reported distance (relative + absolute, m).
constexpr double kCertifyRelative = 1e-6;
constexpr double kCertifyAbsolute = 1e-10;

// Largest extent of a centred shape along the world direction u, i.e. max over points x of
// the shape (relative to its centre) of u . x. Returns false for shapes we do not model.
bool shapeExtent(const fcl::CollisionGeometryd& g, const Eigen::Matrix3d& rotation,
                 const Eigen::Vector3d& u, double* extent) {
  const Eigen::Vector3d l = rotation.transpose() * u;
  switch (g.getNodeType()) {
    case fcl::GEOM_BOX:
      *extent = 0.5 * static_cast<const fcl::Boxd&>(g).side.cwiseProduct(l.cwiseAbs()).sum();
      return true;
    case fcl::GEOM_SPHERE:
      *extent = static_cast<const fcl::Sphered&>(g).radius * l.norm();
      return true;
    case fcl::GEOM_CYLINDER: {
      const auto& c = static_cast<const fcl::Cylinderd&>(g);
      *extent = c.radius * l.head<2>().norm() + 0.5 * c.lz * std::abs(l.z());
      return true;
    }
    case fcl::GEOM_CAPSULE: {
      const auto& c = static_cast<const fcl::Capsuled&>(g);
      *extent = c.radius * l.norm() + 0.5 * c.lz * std::abs(l.z());
      return true;
    }
    default:
      return false;
  }
}

// Gap between the projections of a and b on the unit axis n: a true lower bound on their
// distance whatever n is (projection never lengthens a segment). Because it does not trust
// any FCL output, it is what conservative advancement steps by.
double axisLowerBound(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                      const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b,
                      const Eigen::Vector3d& n, double fallback) {
  double extent_a = 0.0, extent_b = 0.0;
  if (!shapeExtent(a, pose_a.linear(), n, &extent_a) ||
      !shapeExtent(b, pose_b.linear(), n, &extent_b)) {
    return fallback;  // unknown shape type: nothing better than the solver's own answer
  }
  return n.dot(pose_b.translation() - pose_a.translation()) - extent_a - extent_b;
}

// Unit direction from a's centre to b's, the fallback when nearest points coincide.
Eigen::Vector3d centreDirection(const Eigen::Isometry3d& pose_a, const Eigen::Isometry3d& pose_b) {
  const Eigen::Vector3d d = pose_b.translation() - pose_a.translation();
  const double n = d.norm();
  return n > 1e-12 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::UnitX();
}

// One FCL distance answer plus the lower bound that checks it.
struct Attempt {
  double distance = kInf;
  double lower_bound = -kInf;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

// One FCL distance query with the given solver. Returns false when the solver reports the
// shapes as intersecting (or throws); otherwise fills distance, points and lower bound.
bool distanceAttempt(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                     const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b,
                     fcl::GJKSolverType solver, Attempt* out) {
  // Never request signed distance: FCL 0.7's EPA can throw or loop on touching boxes.
  fcl::DistanceRequestd request(true, false, 0.0, 0.0, kGjkTolerance, solver);
  fcl::DistanceResultd result;
  try {
    fcl::distance(&a, pose_a, &b, pose_b, request, result);
  } catch (const std::exception&) {
    return false;
  }
  if (!(result.min_distance > 0.0)) return false;  // -1 means "intersecting"
  out->point_a = result.nearest_points[0];         // FCL 0.7 returns world-frame points
  out->point_b = result.nearest_points[1];
  const Eigen::Vector3d delta = out->point_b - out->point_a;
  const double length = delta.norm();
  out->normal = length > 1e-12 ? Eigen::Vector3d(delta / length) : centreDirection(pose_a, pose_b);
  out->distance = result.min_distance;
  out->lower_bound = axisLowerBound(a, pose_a, b, pose_b, out->normal, out->distance);
  return true;
}

bool certified(const Attempt& attempt) {
  return attempt.distance - attempt.lower_bound <=
         kCertifyRelative * attempt.distance + kCertifyAbsolute;
}

// Everything one evaluation produces: the public answer plus the certified lower bound.
struct Evaluation {
  ShapeDistance shape;
  double lower_bound = 0.0;  ///< m, never above the true distance (0 when overlapping)
  int queries = 0;           ///< distance queries spent (FCL calls or closed-form)
  bool exact = false;        ///< distance and normal exact (closed form), not just bounded
};

// FCL contact for overlapping shapes. The libccd solver is used here on purpose: for pairs
// without a dedicated routine (a cylinder or capsule against a box, cylinder or capsule)
// FCL 0.7's independent solver (GJK + EPA) returns negative depths and reversed normals,
// while libccd (MPR) returns normals that point from a towards b.
bool contactAttempt(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                    const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b,
                    ShapeDistance* out) {
  fcl::CollisionRequestd request(1, true, 1, false, true, fcl::GST_LIBCCD);
  // One result per thread, cleared and reused: its contact vector keeps its capacity, so
  // overlap queries stop allocating after the first.
  thread_local fcl::CollisionResultd result;
  result.clear();
  try {
    fcl::collide(&a, pose_a, &b, pose_b, request, result);
  } catch (const std::exception&) {
    return false;
  }
  if (!result.isCollision() || result.numContacts() == 0) return false;
  const fcl::Contactd& contact = result.getContact(0);
  out->point_a = contact.pos;  // world frame
  out->point_b = contact.pos;
  // FCL's contact normal points from o1 (a) towards o2 (b): moving b along it separates them.
  const double length = contact.normal.norm();
  out->normal =
      length > 1e-12 ? Eigen::Vector3d(contact.normal / length) : centreDirection(pose_a, pose_b);
  return true;
}

// Two upright boxes (turned about the vertical only, as trackers report people and
// vehicles) have an exact closed-form distance and contact, at a tenth of the cost of an FCL
// query. Returns false when FCL must answer: other shapes and tilted boxes.
bool evaluateUpright(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                     const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b,
                     Evaluation* e) {
  if (a.getNodeType() != fcl::GEOM_BOX || b.getNodeType() != fcl::GEOM_BOX ||
      !isUpright(pose_a.linear()) || !isUpright(pose_b.linear())) {
    return false;
  }
  const UprightBoxDistance d =
      uprightBoxDistance(pose_a, 0.5 * static_cast<const fcl::Boxd&>(a).side, pose_b,
                         0.5 * static_cast<const fcl::Boxd&>(b).side);
  if (!d.solved) return false;
  e->queries = 1;
  e->exact = true;
  e->shape.distance = d.distance;
  e->shape.overlapping = d.overlapping;
  e->shape.point_a = d.point_a;
  e->shape.point_b = d.point_b;
  e->shape.normal = d.normal;
  // Exact up to rounding; shaved by a few ulps so it stays a lower bound.
  e->lower_bound = d.distance * (1.0 - 1e-12);
  return true;
}

// Distance with certification and fallbacks. FCL 0.7 GJK answers are occasionally far too
// large: GST_INDEP on rotated box pairs (~0.1 % of random pairs, up to 2x), GST_LIBCCD on
// axis-aligned box pairs (fcl #508). An answer is accepted only when the separating-axis
// lower bound along its normal agrees; otherwise the other solver is tried and the best
// bounds of both are kept. `want_contact` runs fcl::collide when the shapes may touch.
Evaluation evaluate(const fcl::CollisionGeometryd& a, const Eigen::Isometry3d& pose_a,
                    const fcl::CollisionGeometryd& b, const Eigen::Isometry3d& pose_b,
                    double touch_threshold, bool want_contact) {
  Evaluation e;
  if (evaluateUpright(a, pose_a, b, pose_b, &e)) return e;
  Attempt best;
  bool gjk_inside = false;
  for (fcl::GJKSolverType solver : {fcl::GST_INDEP, fcl::GST_LIBCCD}) {
    Attempt attempt;
    ++e.queries;
    if (!distanceAttempt(a, pose_a, b, pose_b, solver, &attempt)) {
      gjk_inside = true;
      break;
    }
    const double lower_bound = std::max(best.lower_bound, attempt.lower_bound);
    if (attempt.distance < best.distance) best = attempt;
    best.lower_bound = lower_bound;
    if (certified(attempt)) break;
  }

  const bool may_touch = gjk_inside || best.lower_bound <= touch_threshold;
  if (may_touch && want_contact) {
    ++e.queries;
    if (contactAttempt(a, pose_a, b, pose_b, &e.shape)) {
      e.shape.distance = 0.0;
      e.shape.overlapping = true;
      return e;
    }
  } else if (gjk_inside) {
    // Without a contact request GJK's verdict is enough.
    e.shape.distance = 0.0;
    e.shape.overlapping = true;
    return e;
  }

  if (best.distance < kInf) {
    e.shape.distance = best.distance;
    e.shape.point_a = best.point_a;
    e.shape.point_b = best.point_b;
    e.shape.normal = best.normal;
    e.lower_bound = std::max(0.0, best.lower_bound);
    return e;
  }
  // GJK says "intersecting", collide says "apart": the shapes touch within solver tolerance.
  // No nearest points are available; report a touching contact at the centres' midpoint.
  e.shape.distance = 0.0;
  e.shape.point_a = e.shape.point_b = 0.5 * (pose_a.translation() + pose_b.translation());
  e.shape.normal = centreDirection(pose_a, pose_b);
  return e;
}

void checkBody(const NarrowBody& body) {
  if (body.geometry == nullptr || body.motion == nullptr) {
    throw std::invalid_argument("NarrowPhase::predict: body without geometry or motion");
  }
}

// Velocity of a point p rigidly attached to a body, world frame, m/s.
Eigen::Vector3d pointVelocity(const BodyMotion& motion, const Eigen::Vector3d& p) {
  return motion.linear_velocity + motion.angular_velocity.cross(p - motion.position);
}

// Gap between the margin-inflated shapes at time t for the advancement loops.
struct GapProbe {
  const NarrowBody& a;
  const NarrowBody& b;
  int* queries;

  // Certified lower bound on the inflated gap at t, m (-inf when overlapping). No contact
  // point is needed here, so fcl::collide (which allocates) is never called. `normal`
  // receives the unit normal from a towards b and `exact` whether gap and normal are exact.
  double gapAt(double t, Eigen::Vector3d* normal, bool* exact) const {
    const Evaluation e =
        evaluate(*a.geometry, a.motion->poseAt(t), *b.geometry, b.motion->poseAt(t), 0.0, false);
    *queries += e.queries;
    *normal = e.shape.normal;
    *exact = e.exact && !e.shape.overlapping;
    if (e.shape.overlapping) return -kInf;
    return e.lower_bound - a.margin - b.margin;
  }
  double gapAt(double t) const {
    Eigen::Vector3d normal;
    bool exact;
    return gapAt(t, &normal, &exact);
  }
};

}  // namespace

std::shared_ptr<fcl::CollisionGeometryd> makeGeometry(const Shape& shape) {
  if (!shape.valid()) throw std::invalid_argument("makeGeometry: invalid shape");
  switch (shape.type) {
    case ShapeType::kBox:
      return std::make_shared<fcl::Boxd>(2.0 * shape.half_extents);  // FCL takes full sides
    case ShapeType::kSphere:
      return std::make_shared<fcl::Sphered>(shape.radius);
    case ShapeType::kCylinder:
      return std::make_shared<fcl::Cylinderd>(shape.radius, shape.length);
    case ShapeType::kCapsule:
      // FCL's capsule lz is the segment between the hemisphere centres, like Shape::length
      // (its local AABB is radius + lz / 2 along z).
      // A zero-length capsule is a sphere; FCL 0.7's capsule code trips its own asserts
      // (abort) on it against cylinders, found by fuzzing.
      if (shape.length == 0.0) return std::make_shared<fcl::Sphered>(shape.radius);
      return std::make_shared<fcl::Capsuled>(shape.radius, shape.length);
  }
  throw std::invalid_argument("makeGeometry: unknown shape type");
}

NarrowPhase::NarrowPhase(const NarrowPhaseConfig& config) : config_(config) {}

ShapeDistance NarrowPhase::distance(const fcl::CollisionGeometryd& a,
                                    const Eigen::Isometry3d& pose_a,
                                    const fcl::CollisionGeometryd& b,
                                    const Eigen::Isometry3d& pose_b) const {
  return evaluate(a, pose_a, b, pose_b, config_.distance_tolerance, true).shape;
}

ContactPrediction NarrowPhase::predict(const NarrowBody& a, const NarrowBody& b,
                                       TimeInterval window) const {
  checkBody(a);
  checkBody(b);
  ContactPrediction out;

  // The report describes t = 0 on the raw shapes, whatever the window.
  const Eigen::Isometry3d pose_a0 = a.motion->poseAt(0.0);
  const Eigen::Isometry3d pose_b0 = b.motion->poseAt(0.0);
  const Evaluation now =
      evaluate(*a.geometry, pose_a0, *b.geometry, pose_b0, config_.distance_tolerance, true);
  out.iterations = now.queries;
  out.distance = std::max(0.0, now.shape.distance - a.margin - b.margin);
  out.point_a = now.shape.point_a;
  out.point_b = now.shape.point_b;
  out.normal = now.shape.normal;
  out.closing_speed =
      out.normal.dot(pointVelocity(*a.motion, out.point_a) - pointVelocity(*b.motion, out.point_b));
  if (window.empty()) return out;
  bool separation_known = false;

  // Two boxes that only translate: the moving separating-axis test gives the contact
  // interval in closed form, exact without margins and conservative with them, at no FCL
  // cost. Trackers report most objects this way.
  if (a.geometry->getNodeType() == fcl::GEOM_BOX && b.geometry->getNodeType() == fcl::GEOM_BOX &&
      a.motion->angular_velocity.isZero(0.0) && b.motion->angular_velocity.isZero(0.0) &&
      a.motion->linear_velocity.allFinite() && b.motion->linear_velocity.allFinite()) {
    const auto& box_a = static_cast<const fcl::Boxd&>(*a.geometry);
    const auto& box_b = static_cast<const fcl::Boxd&>(*b.geometry);
    const TimeInterval contact = movingBoxInterval(
        pose_a0, 0.5 * box_a.side, a.motion->linear_velocity, pose_b0, 0.5 * box_b.side,
        b.motion->linear_velocity, a.margin + b.margin, window);
    if (contact.empty()) return out;
    if (a.margin + b.margin == 0.0) {
      out.contact = true;
      out.time_to_contact = contact.first;
      out.time_to_separation = contact.last;
      return out;
    }
    // With margins the boxes are rounded, which the axis test bounds but does not match at
    // edges and corners: conservative advancement finds the first contact inside the
    // narrowed window. The axis test's exit time stands as the last contact (never early).
    window = contact;
    separation_known = true;
  }

  // Upper bound on how fast the gap between any point of a and any point of b can shrink:
  // relative translation plus the fastest rim speed of each rotating body.
  const double mu = (a.motion->linear_velocity - b.motion->linear_velocity).norm() +
                    a.motion->angular_velocity.norm() * a.bounding_radius +
                    b.motion->angular_velocity.norm() * b.bounding_radius;
  if (!std::isfinite(mu)) {
    // Non-finite motion (a caller bug): claim the whole window rather than miss a contact.
    out.contact = true;
    out.time_to_contact = window.first;
    out.time_to_separation = window.last;
    return out;
  }
  const double tol = config_.distance_tolerance;
  const GapProbe probe{a, b, &out.iterations};
  const double gap_now = now.shape.overlapping ? -kInf : now.lower_bound - a.margin - b.margin;

  // Forward advancement: every step is shorter than the time the gap needs to close, so no
  // contact is ever skipped.
  //
  // Two bodies that only translate have a gap g(t) that is convex in t (the distance from
  // the origin to a translating convex set, minus the margins), with g'(t) = n . (v_b - v_a)
  // wherever g > 0 (the nearest point is unique). A convex function lies above its tangents,
  // so with an exact gap and normal (the upright closed form) two shortcuts are safe: the
  // Newton step gap / (-g') never passes the first root, and g' >= 0 means the gap never
  // shrinks again. Newton's step is never shorter than gap / mu and converges in a step or
  // two where conservative advancement creeps along grazing approaches.
  const bool translating =
      a.motion->angular_velocity.isZero(0.0) && b.motion->angular_velocity.isZero(0.0);
  const Eigen::Vector3d relative = b.motion->linear_velocity - a.motion->linear_velocity;
  double t = window.first;
  for (int step = 0; step < config_.max_iterations; ++step) {
    Eigen::Vector3d normal = now.shape.normal;
    bool exact = now.exact && !now.shape.overlapping;
    const double gap = (t == 0.0) ? gap_now : probe.gapAt(t, &normal, &exact);
    if (gap <= tol) break;
    if (!(mu > 0.0)) return out;  // no relative motion: the gap never closes
    double advance = gap / mu;
    if (translating && exact) {
      const double closing = -normal.dot(relative);  // m/s, -g'(t)
      if (!(closing > 0.0)) return out;              // g' >= 0: never closes from here on
      // Shaved by a part in 1e9 so rounding cannot carry it past the root.
      advance = std::max(advance, gap / closing * (1.0 - 1e-9));
    }
    t += advance;
    if (t > window.last) return out;
  }
  // Reached on contact, or out of steps without deciding: contact now is the safe answer.
  out.contact = true;
  out.time_to_contact = t;

  // Backward advancement from the end of the window finds the last contact the same way.
  double s = window.last;
  out.time_to_separation = window.last;
  if (!(mu > 0.0) || separation_known) return out;
  for (int step = 0; step < config_.max_iterations; ++step) {
    if (s <= out.time_to_contact) {
      s = out.time_to_contact;
      break;
    }
    const double gap = probe.gapAt(s);
    if (gap <= tol) break;
    s -= gap / mu;
  }
  out.time_to_separation = std::max(s, out.time_to_contact);
  return out;
}

}  // namespace workspace_proximity
