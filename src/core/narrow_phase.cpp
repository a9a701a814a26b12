#include "workspace_proximity/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "fcl_geometry.hpp"
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

// A shape as the distance queries see it: its dimensions and its FCL geometry.
struct Solid {
  const Shape& shape;
  const fcl::CollisionGeometryd& geometry;
};

// Largest extent of a centred shape along the world direction u, i.e. max over points x of
// the shape (relative to its centre) of u . x.
double shapeExtent(const Shape& shape, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& u) {
  const Eigen::Vector3d l = rotation.transpose() * u;
  switch (shape.type) {
    case ShapeType::kBox:
      return shape.half_extents.cwiseProduct(l.cwiseAbs()).sum();
    case ShapeType::kSphere:
      return shape.radius * l.norm();
    case ShapeType::kCylinder:
      return shape.radius * l.head<2>().norm() + 0.5 * shape.length * std::abs(l.z());
    case ShapeType::kCapsule:
      return shape.radius * l.norm() + 0.5 * shape.length * std::abs(l.z());
  }
  return std::numeric_limits<double>::quiet_NaN();  // unreachable: shapes are valid() here
}

// Gap between the projections of a and b on the unit axis n: a true lower bound on their
// distance whatever n is (projection never lengthens a segment). Because it does not trust
// any FCL output, it is what conservative advancement steps by.
double axisLowerBound(const Solid& a, const Eigen::Isometry3d& pose_a, const Solid& b,
                      const Eigen::Isometry3d& pose_b, const Eigen::Vector3d& n) {
  return n.dot(pose_b.translation() - pose_a.translation()) -
         shapeExtent(a.shape, pose_a.linear(), n) - shapeExtent(b.shape, pose_b.linear(), n);
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
bool distanceAttempt(const Solid& a, const Eigen::Isometry3d& pose_a, const Solid& b,
                     const Eigen::Isometry3d& pose_b, fcl::GJKSolverType solver, Attempt* out) {
  // Never request signed distance: FCL 0.7's EPA can throw or loop on touching boxes.
  fcl::DistanceRequestd request(true, false, 0.0, 0.0, kGjkTolerance, solver);
  fcl::DistanceResultd result;
  try {
    fcl::distance(&a.geometry, pose_a, &b.geometry, pose_b, request, result);
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
  out->lower_bound = axisLowerBound(a, pose_a, b, pose_b, out->normal);
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
bool contactAttempt(const Solid& a, const Eigen::Isometry3d& pose_a, const Solid& b,
                    const Eigen::Isometry3d& pose_b, ShapeDistance* out) {
  fcl::CollisionRequestd request(1, true, 1, false, true, fcl::GST_LIBCCD);
  // One result per thread, cleared and reused: its contact vector keeps its capacity, so
  // overlap queries stop allocating after the first.
  thread_local fcl::CollisionResultd result;
  result.clear();
  try {
    fcl::collide(&a.geometry, pose_a, &b.geometry, pose_b, request, result);
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
bool evaluateUpright(const Shape& a, const Eigen::Isometry3d& pose_a, const Shape& b,
                     const Eigen::Isometry3d& pose_b, Evaluation* e) {
  if (a.type != ShapeType::kBox || b.type != ShapeType::kBox || !isUpright(pose_a.linear()) ||
      !isUpright(pose_b.linear())) {
    return false;
  }
  const UprightBoxDistance d = uprightBoxDistance(pose_a, a.half_extents, pose_b, b.half_extents);
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

// FCL's two solvers, each answer checked against its own lower bound (see evaluate): the
// best answer and the best lower bound go to `best`. False when GJK reports the shapes
// intersecting.
bool fclDistance(const Solid& a, const Eigen::Isometry3d& pose_a, const Solid& b,
                 const Eigen::Isometry3d& pose_b, Attempt* best, int* queries) {
  for (fcl::GJKSolverType solver : {fcl::GST_INDEP, fcl::GST_LIBCCD}) {
    Attempt attempt;
    ++*queries;
    if (!distanceAttempt(a, pose_a, b, pose_b, solver, &attempt)) return false;
    const double lower_bound = std::max(best->lower_bound, attempt.lower_bound);
    if (attempt.distance < best->distance) *best = attempt;
    best->lower_bound = lower_bound;
    if (certified(attempt)) break;
  }
  return true;
}

// Distance with certification and fallbacks. FCL 0.7 GJK answers are occasionally far too
// large: GST_INDEP on rotated box pairs (~0.1 % of random pairs, up to 2x), GST_LIBCCD on
// axis-aligned box pairs (fcl #508). An answer is accepted only when the separating-axis
// lower bound along its normal agrees; otherwise the other solver is tried and the best
// bounds of both are kept. `want_contact` runs fcl::collide when the shapes may touch.
Evaluation evaluate(const Solid& a, const Eigen::Isometry3d& pose_a, const Solid& b,
                    const Eigen::Isometry3d& pose_b, double touch_threshold, bool want_contact) {
  Evaluation e;
  if (evaluateUpright(a.shape, pose_a, b.shape, pose_b, &e)) return e;
  Attempt best;
  const bool gjk_inside = !fclDistance(a, pose_a, b, pose_b, &best, &e.queries);
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

void checkBody(const PairBody& body) {
  if (body.shape == nullptr || body.motion == nullptr) {
    throw std::invalid_argument("NarrowPhase::predict: body without shape or motion");
  }
}

// Velocity of a point p rigidly attached to a body, world frame, m/s.
Eigen::Vector3d pointVelocity(const BodyMotion& motion, const Eigen::Vector3d& p) {
  return motion.linear_velocity + motion.angular_velocity.cross(p - motion.position);
}

// Fastest speed of any point of a body relative to its centre, m/s (0 when not turning).
double rimSpeed(const PairBody& body) {
  const double w = body.motion->angular_velocity.norm();
  return w == 0.0 ? 0.0 : w * body.shape->boundingRadius();
}

// Upper bound on how fast the gap between any point of a and any point of b can shrink, m/s:
// relative translation plus the fastest rim speed of each rotating body.
double closingSpeedBound(const PairBody& a, const PairBody& b) {
  return (a.motion->linear_velocity - b.motion->linear_velocity).norm() + rimSpeed(a) + rimSpeed(b);
}

// Pose at t of a body with `motion` whose pose at t = 0 is `now` (or null): a body that does not
// turn keeps now's rotation matrix (bit for bit what poseAt builds again from the quaternion).
Eigen::Isometry3d poseAtFrom(const BodyMotion& motion, const Eigen::Isometry3d* now, double t) {
  if (now == nullptr || !isExactlyZero(motion.angular_velocity)) return motion.poseAt(t);
  Eigen::Isometry3d pose = *now;
  pose.translation() = motion.position + motion.linear_velocity * t;
  return pose;
}

// One query's pair: both shapes with their geometry, motions and margins, and the count of
// distance queries spent. pose_a / pose_b: the poses at t = 0 when the caller has them.
struct MovingPair {
  Solid a, b;
  const BodyMotion& motion_a;
  const BodyMotion& motion_b;
  double margin_a, margin_b;
  int* queries;
  const Eigen::Isometry3d* pose_a = nullptr;
  const Eigen::Isometry3d* pose_b = nullptr;

  // Certified lower bound on the inflated gap at t, m (-inf when overlapping). No contact
  // point is needed here, so fcl::collide (which allocates) is never called. `normal`
  // receives the unit normal from a towards b and `exact` whether gap and normal are exact.
  double gapAt(double t, Eigen::Vector3d* normal, bool* exact) const {
    const Evaluation e = evaluate(a, poseAtFrom(motion_a, pose_a, t), b,
                                  poseAtFrom(motion_b, pose_b, t), 0.0, false);
    *queries += e.queries;
    *normal = e.shape.normal;
    *exact = e.exact && !e.shape.overlapping;
    if (e.shape.overlapping) return -kInf;
    return e.lower_bound - margin_a - margin_b;
  }
  double gapAt(double t) const {
    Eigen::Vector3d normal;
    bool exact;
    return gapAt(t, &normal, &exact);
  }
};

// The report at t = 0 on the raw shapes: distance, nearest points, normal, closing speed.
Evaluation describeNow(const MovingPair& pair, const PairBody& a, const PairBody& b,
                       double tolerance, ContactPrediction* out) {
  Eigen::Isometry3d scratch_a, scratch_b;
  const Evaluation now = evaluate(pair.a, a.poseNow(&scratch_a), pair.b, b.poseNow(&scratch_b),
                                  tolerance, true);
  out->iterations = now.queries;
  out->distance = std::max(0.0, now.shape.distance - pair.margin_a - pair.margin_b);
  out->point_a = now.shape.point_a;
  out->point_b = now.shape.point_b;
  out->normal = now.shape.normal;
  out->closing_speed = out->normal.dot(pointVelocity(pair.motion_a, out->point_a) -
                                       pointVelocity(pair.motion_b, out->point_b));
  return now;
}

// describeNow() for two upright boxes whose poses now the caller has, straight from the closed
// form (what evaluate() would pick, bit for bit), without FCL's geometry or the query's set-up:
// the whole of a query whose window is exact. False: the general path must answer.
bool reportUpright(const PairBody& a, const PairBody& b, ContactPrediction* out) {
  if (a.shape->type != ShapeType::kBox || b.shape->type != ShapeType::kBox || a.pose == nullptr ||
      b.pose == nullptr || !isUpright(a.pose->linear()) || !isUpright(b.pose->linear())) {
    return false;
  }
  const UprightBoxDistance d =
      uprightBoxDistance(*a.pose, a.shape->half_extents, *b.pose, b.shape->half_extents);
  if (!d.solved) return false;
  out->iterations = 1;
  out->distance = std::max(0.0, d.distance - a.margin - b.margin);
  out->point_a = d.point_a;
  out->point_b = d.point_b;
  out->normal = d.normal;
  out->closing_speed = out->normal.dot(pointVelocity(*a.motion, out->point_a) -
                                       pointVelocity(*b.motion, out->point_b));
  return true;
}

// Forward advancement from the window's start: every step is shorter than the time the gap
// needs to close, so no contact is ever skipped. Returns false when the shapes do not touch
// within the window; else `t` is the first contact (or where the steps ran out: contact then
// is the safe answer).
//
// Two bodies that only translate have a gap g(t) that is convex in t (the distance from the
// origin to a translating convex set, minus the margins), with g'(t) = n . (v_b - v_a)
// wherever g > 0 (the nearest point is unique). A convex function lies above its tangents,
// so with an exact gap and normal (the upright closed form) two shortcuts are safe: the
// Newton step gap / (-g') never passes the first root, and g' >= 0 means the gap never
// shrinks again. Newton's step is never shorter than gap / mu and converges in a step or two
// where conservative advancement creeps along grazing approaches.
bool advanceToFirstContact(const MovingPair& pair, const Evaluation& now, double mu,
                           TimeInterval window, const NarrowPhaseConfig& config, double* t) {
  const double gap_now = now.shape.overlapping ? -kInf : now.lower_bound - pair.margin_a - pair.margin_b;
  const bool translating =
      isExactlyZero(pair.motion_a.angular_velocity) && isExactlyZero(pair.motion_b.angular_velocity);
  const Eigen::Vector3d relative = pair.motion_b.linear_velocity - pair.motion_a.linear_velocity;
  *t = window.first;
  for (int step = 0; step < config.max_iterations; ++step) {
    Eigen::Vector3d normal = now.shape.normal;
    bool exact = now.exact && !now.shape.overlapping;
    const double gap = (*t == 0.0) ? gap_now : pair.gapAt(*t, &normal, &exact);
    if (gap <= config.distance_tolerance) break;
    if (!(mu > 0.0)) return false;  // no relative motion: the gap never closes
    double advance = gap / mu;
    if (translating && exact) {
      const double closing = -normal.dot(relative);  // m/s, -g'(t)
      if (!(closing > 0.0)) return false;            // g' >= 0: never closes from here on
      // Shaved by a part in 1e9 so rounding cannot carry it past the root.
      advance = std::max(advance, gap / closing * (1.0 - 1e-9));
    }
    *t += advance;
    if (*t > window.last) return false;
  }
  return true;
}

// Backward advancement from the window's end finds the last contact the same way; never
// before the first contact.
double retreatToLastContact(const MovingPair& pair, double mu, double end, double first,
                            const NarrowPhaseConfig& config) {
  double s = end;
  for (int step = 0; step < config.max_iterations; ++step) {
    if (s <= first) {
      s = first;
      break;
    }
    const double gap = pair.gapAt(s);
    if (gap <= config.distance_tolerance) break;
    s -= gap / mu;
  }
  return std::max(s, first);
}

// ------------------------------------------------------------------------------------------
// Piecewise motion and growing margins: the same advancement, piece by piece.

// Fastest speed of any point of a shape relative to its centre under `motion`, m/s.
double rimSpeed(const Shape& shape, const BodyMotion& motion) {
  const double w = motion.angular_velocity.norm();
  return w == 0.0 ? 0.0 : w * shape.boundingRadius();
}

// The gap of a pair on one piece (PairPieces): each body in its segment, its margin that
// segment's, grown by its growth polynomial unless `with_growth` is false.
struct PieceGap {
  const Solid& a;
  const Solid& b;
  const Piece& piece;
  bool with_growth;
  int* queries;

  double margins(double t) const {
    double m = piece.a.segment->margin + piece.b.segment->margin;
    if (with_growth) m += piece.a.growth.at(t - piece.u0) + piece.b.growth.at(t - piece.u0);
    return m;
  }
  // Certified lower bound on the gap at t (within the piece), m; -inf when overlapping.
  double gapAt(double t, Eigen::Vector3d* normal, bool* exact) const {
    const Evaluation e = evaluate(a, piece.a.poseAt(t), b, piece.b.poseAt(t), 0.0, false);
    *queries += e.queries;
    *normal = e.shape.normal;
    *exact = e.exact && !e.shape.overlapping;
    if (e.shape.overlapping) return -kInf;
    return e.lower_bound - margins(t);
  }
  // How fast the gap can shrink on the piece, m/s: relative translation, both rim speeds, and
  // (with growth) both growth rates at their largest on the piece.
  double closingBound() const {
    const BodyMotion& ma = piece.a.segment->motion;
    const BodyMotion& mb = piece.b.segment->motion;
    double mu = (ma.linear_velocity - mb.linear_velocity).norm() + rimSpeed(a.shape, ma) +
                rimSpeed(b.shape, mb);
    if (with_growth) mu += piece.a.growth_rate + piece.b.growth_rate;
    return mu;
  }
  // Newton steps stay safe where the gap is convex in t: both bodies only translate on the
  // piece (the distance of two translating convex sets is convex) and the growth subtracted
  // from it is linear (a quadratic growth, max_accel > 0 before the cap takes over, makes
  // the gap convex minus convex: then plain advancement only).
  bool convex() const {
    return isExactlyZero(piece.a.segment->motion.angular_velocity) &&
           isExactlyZero(piece.b.segment->motion.angular_velocity) &&
           (!with_growth || (piece.a.growth.linear() && piece.b.growth.linear()));
  }
  // The gap's rate of change from the growth alone (linear growth), m/s.
  double growthSlope() const { return with_growth ? piece.a.growth.c1 + piece.b.growth.c1 : 0.0; }
  Eigen::Vector3d relativeVelocity() const {
    return piece.b.segment->motion.linear_velocity - piece.a.segment->motion.linear_velocity;
  }
};

// Forward advancement over the pieces, from the window's start: on each piece whose axis
// window is not empty, steps that never pass a contact (as advanceToFirstContact); a piece
// without contact hands over at its end, where the next segment starts. Returns false when no
// contact is found; true with *t the first contact (or where the steps ran out: contact then).
bool firstContactOnPieces(const Solid& a, const Solid& b, const PairPieces& pieces,
                          TimeInterval window, const NarrowPhaseConfig& config, int* queries,
                          double* t_out) {
  double t = window.first;
  int steps = 0;
  for (int i = pieces.pieceAt(t); i < pieces.size(); ++i) {
    const Piece p = pieces.piece(i);
    if (p.u0 > window.last) break;
    const TimeInterval w = pieces.axisWindowOf(i, p);
    const double lo = std::max(t, w.first), hi = std::min(w.last, window.last);
    if (!w.empty() && lo <= hi) {
      t = lo;
      const PieceGap gap{a, b, p, true, queries};
      const double mu = gap.closingBound();
      const bool convex = gap.convex();
      for (;;) {
        if (steps++ >= config.max_iterations) {
          *t_out = t;
          return true;
        }
        Eigen::Vector3d normal;
        bool exact = false;
        const double g = gap.gapAt(t, &normal, &exact);
        if (g <= config.distance_tolerance) {
          *t_out = t;
          return true;
        }
        if (!(mu > 0.0)) break;  // nothing moves or grows on this piece: the gap stays
        double advance = g / mu;
        if (convex && exact) {
          const double closing = -normal.dot(gap.relativeVelocity()) + gap.growthSlope();
          if (!(closing > 0.0)) break;  // never shrinks again on this piece
          advance = std::max(advance, g / closing * (1.0 - 1e-9));
        }
        t += advance;
        if (t > hi) break;
      }
    }
    t = p.u1;  // the next piece starts here, with its own segments
  }
  return false;
}

// Backward advancement over the pieces from `end` down to `first`: the last contact of the
// shapes grown by their segment margins, without growth (a growing set has no last contact;
// the message reports the constant-velocity one). Never earlier than that last contact, never
// before `first`; `first` when those shapes never touch.
double lastContactOnPieces(const Solid& a, const Solid& b, const PairPieces& pieces, double first,
                           double end, const NarrowPhaseConfig& config, int* queries) {
  double s = end;
  int steps = 0;
  for (int i = pieces.pieceAt(end); i >= 0; --i) {
    const Piece p = pieces.piece(i);
    if (p.u1 < first) break;
    const TimeInterval w = pieceAxisWindow(p, false);
    const double hi = std::min(s, w.last), lo = std::max(first, w.first);
    if (!w.empty() && lo <= hi) {
      s = hi;
      const PieceGap gap{a, b, p, false, queries};
      const double mu = gap.closingBound();
      for (;;) {
        if (steps++ >= config.max_iterations) return std::max(s, first);  // safe: not early
        Eigen::Vector3d normal;
        bool exact = false;
        const double g = gap.gapAt(s, &normal, &exact);
        if (g <= config.distance_tolerance) return std::max(s, first);
        if (!(mu > 0.0)) break;
        s -= g / mu;
        if (s < lo) break;
      }
    }
    s = p.u0;  // the previous piece ends here
  }
  return first;
}

}  // namespace

// FCL geometry by slot; a body without one gets its geometry built for the query.
struct NarrowPhase::GeometryCache {
  std::vector<std::unique_ptr<fcl::CollisionGeometryd>> by_slot;

  const fcl::CollisionGeometryd& of(const PairBody& body,
                                    std::unique_ptr<fcl::CollisionGeometryd>* own) const {
    if (body.geometry < 0) {
      *own = makeFclGeometry(*body.shape);
      return **own;
    }
    const std::size_t slot = static_cast<std::size_t>(body.geometry);
    if (slot >= by_slot.size() || !by_slot[slot]) {
      throw std::invalid_argument("NarrowPhase::predict: no geometry in slot " +
                                  std::to_string(body.geometry));
    }
    return *by_slot[slot];
  }
};

NarrowPhase::NarrowPhase(const NarrowPhaseConfig& config)
    : config_(config), cache_(std::make_unique<GeometryCache>()) {}
NarrowPhase::~NarrowPhase() = default;
NarrowPhase::NarrowPhase(NarrowPhase&&) noexcept = default;
NarrowPhase& NarrowPhase::operator=(NarrowPhase&&) noexcept = default;

void NarrowPhase::setShape(std::int32_t slot, const Shape& shape) {
  if (slot < 0) throw std::invalid_argument("NarrowPhase::setShape: negative slot");
  std::unique_ptr<fcl::CollisionGeometryd> geometry = makeFclGeometry(shape);
  std::vector<std::unique_ptr<fcl::CollisionGeometryd>>& slots = cache_->by_slot;
  if (static_cast<std::size_t>(slot) >= slots.size()) slots.resize(static_cast<std::size_t>(slot) + 1);
  slots[static_cast<std::size_t>(slot)] = std::move(geometry);
}

void NarrowPhase::clearShape(std::int32_t slot) {
  if (slot >= 0 && static_cast<std::size_t>(slot) < cache_->by_slot.size()) {
    cache_->by_slot[static_cast<std::size_t>(slot)].reset();
  }
}

ShapeDistance NarrowPhase::distance(const Shape& a, const Eigen::Isometry3d& pose_a,
                                    const Shape& b, const Eigen::Isometry3d& pose_b) const {
  const std::unique_ptr<fcl::CollisionGeometryd> ga = makeFclGeometry(a), gb = makeFclGeometry(b);
  return evaluate(Solid{a, *ga}, pose_a, Solid{b, *gb}, pose_b, config_.distance_tolerance, true)
      .shape;
}

ShapeDistance NarrowPhase::distanceNow(const PairBody& a, const PairBody& b) const {
  checkBody(a);
  checkBody(b);
  std::unique_ptr<fcl::CollisionGeometryd> own_a, own_b;  // bodies without a cached geometry
  Eigen::Isometry3d scratch_a, scratch_b;
  return evaluate(Solid{*a.shape, cache_->of(a, &own_a)}, a.poseNow(&scratch_a),
                  Solid{*b.shape, cache_->of(b, &own_b)}, b.poseNow(&scratch_b),
                  config_.distance_tolerance, true)
      .shape;
}

ContactPrediction NarrowPhase::predict(const PairBody& a, const PairBody& b,
                                       const ContactWindow& window) const {
  checkBody(a);
  checkBody(b);
  if (window.pieces != nullptr) return predictOnPieces(a, b, window);
  if (a.piecewise() || b.piecewise()) {
    throw std::invalid_argument(
        "NarrowPhase::predict: a body with a path or a growing margin needs piecewiseWindow()");
  }
  ContactPrediction out;
  if (window.exact && reportUpright(a, b, &out)) {
    // Nothing left to refine (e.g. roundedUprightInterval): the report now was all.
    if (window.empty()) return out;
    out.contact = true;
    out.time_to_contact = window.interval.first;
    out.time_to_separation = window.interval.last;
    return out;
  }
  std::unique_ptr<fcl::CollisionGeometryd> own_a, own_b;  // bodies without a cached geometry
  const MovingPair pair{Solid{*a.shape, cache_->of(a, &own_a)}, Solid{*b.shape, cache_->of(b, &own_b)},
                        *a.motion, *b.motion, a.margin, b.margin, &out.iterations, a.pose, b.pose};
  const Evaluation now = describeNow(pair, a, b, config_.distance_tolerance, &out);
  if (window.empty()) return out;
  const TimeInterval w = window.interval;
  const double mu = window.exact ? 0.0 : closingSpeedBound(a, b);
  if (window.exact || !std::isfinite(mu)) {
    // Exact already, or non-finite motion (a caller bug): the whole window, rather than
    // miss a contact.
    out.contact = true;
    out.time_to_contact = w.first;
    out.time_to_separation = w.last;
    return out;
  }
  if (!advanceToFirstContact(pair, now, mu, w, config_, &out.time_to_contact)) {
    out.time_to_contact = 0.0;
    return out;
  }
  out.contact = true;
  out.time_to_separation = w.last;
  if (mu > 0.0 && !window.last_known) {
    out.time_to_separation =
        retreatToLastContact(pair, mu, w.last, out.time_to_contact, config_);
  }
  return out;
}

}  // namespace workspace_proximity

namespace workspace_proximity {

ContactPrediction NarrowPhase::predictOnPieces(const PairBody& a, const PairBody& b,
                                               const ContactWindow& window) const {
  std::unique_ptr<fcl::CollisionGeometryd> own_a, own_b;
  ContactPrediction out;
  const Solid solid_a{*a.shape, cache_->of(a, &own_a)};
  const Solid solid_b{*b.shape, cache_->of(b, &own_b)};
  const PairPieces& pieces = *window.pieces;
  // Now: the first piece's margins, with the growth since each observation.
  const Piece now = pieces.piece(0);
  const double margin_a = now.a.segment->margin + (a.growth != nullptr ? a.growth->at(0.0) : 0.0);
  const double margin_b = now.b.segment->margin + (b.growth != nullptr ? b.growth->at(0.0) : 0.0);
  const MovingPair pair{solid_a, solid_b, *a.motion, *b.motion, margin_a, margin_b, &out.iterations};
  describeNow(pair, a, b, config_.distance_tolerance, &out);
  if (window.empty()) return out;
  if (!firstContactOnPieces(solid_a, solid_b, pieces, window.interval, config_, &out.iterations,
                            &out.time_to_contact)) {
    out.time_to_contact = 0.0;
    return out;
  }
  out.contact = true;
  out.time_to_separation = lastContactOnPieces(solid_a, solid_b, pieces, out.time_to_contact,
                                               window.interval.last, config_, &out.iterations);
  return out;
}

}  // namespace workspace_proximity
