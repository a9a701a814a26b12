#include "workspace_proximity/contact_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "upright_corners.hpp"
#include "workspace_proximity/upright_box_distance.hpp"

namespace workspace_proximity {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A body without a path as one segment over the whole horizon.
const PathSegment* ownSegment(const PairBody& body, double horizon, PathSegment* own) {
  if (body.segments != nullptr) return body.segments;
  own->start = 0.0;
  own->end = horizon;
  own->motion = *body.motion;
  own->extra_margin = 0.0;
  own->margin = body.margin;
  own->half = body.half;
  return own;
}

// Trackers report most objects as boxes that only translate: they have a closed form.
bool translatingBox(const Shape& shape, const BodyMotion& motion) {
  return shape.type == ShapeType::kBox && isExactlyZero(motion.angular_velocity) &&
         motion.linear_velocity.allFinite();
}

}  // namespace

TimeInterval axisWindow(const PairBody& a, const PairBody& b, double horizon) {
  return boxContactInterval(a.motion->position, a.half, a.motion->linear_velocity,
                            b.motion->position, b.half, b.motion->linear_velocity, horizon);
}

ContactWindow refineWindow(const PairBody& a, const PairBody& b, TimeInterval window) {
  ContactWindow w;
  w.axis = window;
  w.interval = window;
  if (window.empty() || !translatingBox(*a.shape, *a.motion) ||
      !translatingBox(*b.shape, *b.motion)) {
    return w;
  }
  const double margins = a.margin + b.margin;
  Eigen::Isometry3d scratch_a, scratch_b;
  const Eigen::Isometry3d& pose_a = a.poseNow(&scratch_a);
  const Eigen::Isometry3d& pose_b = b.poseNow(&scratch_b);
  w.last_known = true;
  // Rounded upright boxes (people, carts and vehicles as trackers report them, with margins):
  // the footprints' corners make the interval exact; the narrow phase has nothing to refine.
  if (margins > 0.0 && isUpright(pose_a.linear()) && isUpright(pose_b.linear()) &&
      roundedUprightInterval(pose_a, a.shape->half_extents, a.motion->linear_velocity, pose_b,
                             b.shape->half_extents, b.motion->linear_velocity, margins, window,
                             &w.interval)) {
    w.exact = true;
    return w;
  }
  // The moving separating-axis test: exact without margins, and with them (rounded boxes) an
  // interval that contains every contact, whose exit time stands as the last contact.
  w.interval = movingBoxInterval(pose_a, a.shape->half_extents, a.motion->linear_velocity,
                                 pose_b, b.shape->half_extents, b.motion->linear_velocity,
                                 margins, window);
  w.exact = margins == 0.0;
  return w;
}

ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon) {
  return refineWindow(a, b, axisWindow(a, b, horizon));
}

PairPieces::PairPieces(const PairBody& a, const PairBody& b, double horizon)
    : a_(&a), b_(&b), horizon_(std::max(horizon, 0.0)) {
  segments_a_ = ownSegment(a, horizon_, &own_a_);
  segments_b_ = ownSegment(b, horizon_, &own_b_);
  first_pose_a_ = firstPose(a, segments_a_);
  first_pose_b_ = firstPose(b, segments_b_);
  const int na = a.segments != nullptr ? usedSegments(a.segments, a.segment_count, horizon_) : 1;
  const int nb = b.segments != nullptr ? usedSegments(b.segments, b.segment_count, horizon_) : 1;
  // The instants the growth caps take over, when inside the horizon.
  double cap_a = a.growth != nullptr ? a.growth->capTime() : kInf;
  double cap_b = b.growth != nullptr ? b.growth->capTime() : kInf;
  if (!(cap_a > 0.0)) cap_a = kInf;
  if (!(cap_b > 0.0)) cap_b = kInf;

  // Merge the breakpoints: each piece keeps the segments in force at its start.
  int ia = 1, ib = 1, sa = 0, sb = 0;
  double current = 0.0;
  breaks_[0] = 0.0;
  for (;;) {
    double next = horizon_;
    if (ia < na) next = std::min(next, segments_a_[ia].start);
    if (ib < nb) next = std::min(next, segments_b_[ib].start);
    next = std::min({next, cap_a, cap_b});
    if (next > current) {
      segment_a_[count_] = static_cast<std::int16_t>(sa);
      segment_b_[count_] = static_cast<std::int16_t>(sb);
      breaks_[++count_] = next;
      current = next;
    }
    if (next >= horizon_) break;
    while (ia < na && segments_a_[ia].start <= next) sa = ia++;
    while (ib < nb && segments_b_[ib].start <= next) sb = ib++;
    if (cap_a <= next) cap_a = kInf;
    if (cap_b <= next) cap_b = kInf;
  }
  if (count_ == 0) {  // horizon 0: one instant
    segment_a_[0] = segment_b_[0] = 0;
    breaks_[1] = 0.0;
    count_ = 1;
  }
}

const Eigen::Isometry3d* PairPieces::firstPose(const PairBody& body, const PathSegment* segments) {
  // The first segment's motion is the body's (PairBody::segments), starting at 0: its pose
  // there is the body's pose now, if the caller has it (the orientation checked, so that a
  // segment that says otherwise builds its own).
  if (body.pose == nullptr || body.motion == nullptr || segments[0].start != 0.0 ||
      segments[0].motion.orientation.coeffs() != body.motion->orientation.coeffs()) {
    return nullptr;
  }
  return body.pose;
}

PieceBody PairPieces::body(const PairBody& body, const PathSegment* segments, int segment,
                           const Eigen::Isometry3d* first_pose, double u0, double u1) const {
  PieceBody p;
  p.segment = &segments[segment];
  p.centre = p.segment->centreAt(u0);
  if (segment == 0) p.start_pose = first_pose;
  if (body.growth != nullptr) {
    p.growth = growthPiece(*body.growth, u0, u1);
    p.growth_rate = body.growth->maxRate(u0, u1);
  }
  return p;
}

Piece PairPieces::piece(int i) const {
  Piece p;
  p.u0 = breaks_[i];
  p.u1 = breaks_[i + 1];
  p.a = body(*a_, segments_a_, segment_a_[i], first_pose_a_, p.u0, p.u1);
  p.b = body(*b_, segments_b_, segment_b_[i], first_pose_b_, p.u0, p.u1);
  return p;
}

int PairPieces::pieceAt(double t) const {
  int i = 0;
  while (i + 1 < count_ && breaks_[i + 1] <= t) ++i;
  return i;
}

TimeInterval pieceAxisWindow(const Piece& piece, bool with_growth) {
  const double zero[3] = {0.0, 0.0, 0.0};
  const double grow_a[3] = {piece.a.growth.c0, piece.a.growth.c1, piece.a.growth.c2};
  const double grow_b[3] = {piece.b.growth.c0, piece.b.growth.c1, piece.b.growth.c2};
  const PathSegment& sa = *piece.a.segment;
  const PathSegment& sb = *piece.b.segment;
  TimeInterval result{piece.u0, piece.u1};
  for (int k = 0; k < 3; ++k) {
    const TimeInterval axis = growingAxisInterval(
        piece.a.centre[k], sa.half[k], sa.motion.linear_velocity[k], with_growth ? grow_a : zero,
        piece.b.centre[k], sb.half[k], sb.motion.linear_velocity[k], with_growth ? grow_b : zero,
        piece.u1 - piece.u0);
    if (axis.empty()) return TimeInterval{};
    result.first = std::max(result.first, widenDown(piece.u0 + axis.first));
    result.last = std::min(result.last, widenUp(piece.u0 + axis.last));
    if (result.empty()) return TimeInterval{};
  }
  return result;
}

TimeInterval PairPieces::axisWindowOf(int i, const Piece& p) const {
  if (i >= kRemembered) return pieceAxisWindow(p);
  const std::uint32_t bit = std::uint32_t{1} << i;
  if ((windows_known_ & bit) == 0) {
    const TimeInterval w = pieceAxisWindow(p);
    window_first_[i] = w.first;
    window_last_[i] = w.last;
    windows_known_ |= bit;
    return w;
  }
  TimeInterval w;
  w.first = window_first_[i];
  w.last = window_last_[i];
  return w;
}

ContactWindow piecewiseWindow(const PairPieces& pieces) {
  ContactWindow w;
  w.pieces = &pieces;
  TimeInterval hull;  // empty
  bool any = false;
  for (int i = 0; i < pieces.size(); ++i) {
    const TimeInterval piece = pieces.axisWindowOf(i, pieces.piece(i));
    if (piece.empty()) continue;
    if (!any) hull.first = piece.first;
    hull.last = piece.last;
    any = true;
  }
  w.axis = hull;
  w.interval = hull;
  return w;
}

namespace {

using upright::Vec2;
using upright::nearestCornerTo;

// ------------------------------------------------------------------------------------------
// Rounded upright boxes in translation (roundedUprightInterval). Everything happens in the
// two footprints' frames: a's centred at the origin, b's at b's centre relative to a's, which
// moves linearly, so every coordinate below is x0 + x1 t.

using std::abs;

// Narrows [*first, *last] to the instants at which |x0 + x1 t| <= reach.
inline void clipAbs(double x0, double x1, double reach, double* first, double* last) {
  if (x1 == 0.0) {
    if (abs(x0) > reach) *first = HUGE_VAL;  // never: empty
    return;
  }
  const double t0 = (-reach - x0) / x1, t1 = (reach - x0) / x1;
  *first = std::max(*first, widenDown(std::min(t0, t1)));
  *last = std::min(*last, widenUp(std::max(t0, t1)));
}

// One footprint seen from another's frame: the other's centre `c` and half-size vectors
// `eu`, `ev` there; the frame's own half sizes hu, hv.
struct View {
  Vec2 c, eu, ev;
  double hu, hv;
};

// Among the viewed footprint's corners, the nearest to the frame's rectangle: the squared
// distance, whether the rectangle's nearest point is a corner too, and the vector from that
// point to the corner (in the frame).
double nearestCornerIn(const View& s, bool* corner_pair, Vec2* between) {
  Vec2 corner, on_self;
  const double d2 = nearestCornerTo(Vec2(s.hu, s.hv), s.c, s.eu, s.ev, &corner, &on_self);
  *corner_pair = abs(corner.x()) > s.hu && abs(corner.y()) > s.hv;
  *between = corner - on_self;
  return d2;
}

// Does the viewed footprint touch the frame's face with normal along the frame's axis k (0:
// u, 1: v, on the side of its centre) with its nearest corner (or, when parallel, an edge)
// within that face? Then the footprints' distance is their gap along that axis.
bool onFace(const View& s, int k) {
  const int j = 1 - k;
  const double side = s.c[k] < 0.0 ? -1.0 : 1.0;
  double along = s.c[j], spread = 0.0;
  for (const Vec2* e : {&s.eu, &s.ev}) {
    const double toward = side * (*e)[k];
    if (abs(toward) > 1e-12 * (abs((*e)[0]) + abs((*e)[1]))) {
      along -= toward > 0.0 ? (*e)[j] : -(*e)[j];  // the corner on self's side
    } else {
      spread += abs((*e)[j]);  // parallel: a whole edge faces the frame's face
    }
  }
  return abs(along) <= (k == 0 ? s.hv : s.hu) + spread;
}

// How far apart two footprints are that do not overlap.
struct FootprintGap {
  double distance = 0.0;  // m
  bool corner_pair = false;  // both nearest points are corners
  Vec2 corners = Vec2::Zero();  // then b's corner minus a's, in world x-y
};

}  // namespace

bool roundedUprightInterval(const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                            const Eigen::Vector3d& velocity_a, const Eigen::Isometry3d& pose_b,
                            const Eigen::Vector3d& half_b, const Eigen::Vector3d& velocity_b,
                            double inflation, TimeInterval window, TimeInterval* out) {
  const Eigen::Vector3d d = pose_b.translation() - pose_a.translation();
  const Eigen::Vector3d w = velocity_b - velocity_a;
  if (!(inflation > 0.0) || !std::isfinite(window.first) || !std::isfinite(window.last) ||
      !d.allFinite() || !w.allFinite()) {
    return false;
  }
  if (window.empty()) {
    *out = TimeInterval{};
    return true;
  }
  const Eigen::Matrix3d& ra = pose_a.linear();
  const Eigen::Matrix3d& rb = pose_b.linear();
  const Vec2 ua(ra(0, 0), ra(1, 0)), va(ra(0, 1), ra(1, 1));
  const Vec2 ub(rb(0, 0), rb(1, 0)), vb(rb(0, 1), rb(1, 1));
  const double c11 = ua.dot(ub), c12 = ua.dot(vb), c21 = va.dot(ub), c22 = va.dot(vb);
  const Vec2 d2 = d.head<2>(), w2 = w.head<2>();
  // b seen from a (its centre at pa0 + pa1 t) and a seen from b.
  View in_a{Vec2::Zero(), half_b.x() * Vec2(c11, c21), half_b.y() * Vec2(c12, c22), half_a.x(), half_a.y()};
  View in_b{Vec2::Zero(), half_a.x() * Vec2(c11, c12), half_a.y() * Vec2(c21, c22), half_b.x(), half_b.y()};
  const Vec2 pa0(ua.dot(d2), va.dot(d2)), pa1(ua.dot(w2), va.dot(w2));
  const Vec2 pb0(-ub.dot(d2), -vb.dot(d2)), pb1(-ub.dot(w2), -vb.dot(w2));
  // Each frame's half sizes plus the other footprint's support on its axes.
  const Vec2 reach_a = Vec2(in_a.hu, in_a.hv) + in_a.eu.cwiseAbs() + in_a.ev.cwiseAbs();
  const Vec2 reach_b = Vec2(in_b.hu, in_b.hv) + in_b.eu.cwiseAbs() + in_b.ev.cwiseAbs();
  // A nanometre (and rounding's share of the scene's size) more: never narrower than exact.
  const double scale = abs(d.x()) + abs(d.y()) + half_a.x() + half_a.y() + half_b.x() +
                       half_b.y() + inflation;  // >= the norms it stands for
  const double radius = inflation + 1e-9 + 64.0 * std::numeric_limits<double>::epsilon() * scale;

  // The separating axes of two vertical prisms (four footprint normals and z), each grown by
  // the inflation: every contact lies in this interval (its ends widened as in
  // axisContactInterval), and at its ends the gap is within the radius but for the corners.
  double first = window.first, last = window.last;
  clipAbs(pa0.x(), pa1.x(), reach_a.x() + inflation, &first, &last);
  clipAbs(pa0.y(), pa1.y(), reach_a.y() + inflation, &first, &last);
  clipAbs(pb0.x(), pb1.x(), reach_b.x() + inflation, &first, &last);
  clipAbs(pb0.y(), pb1.y(), reach_b.y() + inflation, &first, &last);
  const double heights = half_a.z() + half_b.z();
  clipAbs(d.z(), w.z(), heights + inflation, &first, &last);
  if (!(first <= last)) {
    *out = TimeInterval{};
    return true;
  }
  // The footprints decide alone while the heights overlap: the distance is then the
  // footprints' distance. |z gap| is convex in t, so both ends suffice.
  if (w.z() == 0.0 ? abs(d.z()) > heights
                   : abs(d.z() + w.z() * first) > heights || abs(d.z() + w.z() * last) > heights) {
    return false;
  }

  // The footprints' distance at t: cheaply when the separating axis of largest gap has the
  // other footprint's nearest corner on its face (the gap is then the distance), else from
  // the corners (two disjoint convex polygons are nearest at a corner of one of them).
  auto near = [&](double t) {
    in_a.c = pa0 + pa1 * t;
    in_b.c = pb0 + pb1 * t;
    const Vec2 gap_a = in_a.c.cwiseAbs() - reach_a, gap_b = in_b.c.cwiseAbs() - reach_b;
    const int k_a = gap_a.y() > gap_a.x(), k_b = gap_b.y() > gap_b.x();
    const double max_a = gap_a[k_a], max_b = gap_b[k_b];
    return std::max(max_a, max_b) <= 0.0 ||  // overlapping
           (std::max(max_a, max_b) <= radius &&
            (max_a >= max_b ? onFace(in_a, k_a) : onFace(in_b, k_b)));
  };
  auto gap = [&]() {  // at the instant near() last set
    FootprintGap g;
    bool pair_b = false, pair_a = false;
    Vec2 between_b, between_a;
    const double via_b = nearestCornerIn(in_a, &pair_b, &between_b);
    const double via_a = nearestCornerIn(in_b, &pair_a, &between_a);
    if (via_b <= via_a) {
      g.distance = std::sqrt(via_b);
      g.corner_pair = pair_b;
      g.corners = between_b.x() * ua + between_b.y() * va;  // a's corner to b's
    } else {
      g.distance = std::sqrt(via_a);
      g.corner_pair = pair_a;
      g.corners = -(between_a.x() * ub + between_a.y() * vb);  // b's to a's, reversed
    }
    return g;
  };

  // Each end: within reach there (it stays), or in the pocket of two corners that are apart
  // by more (it moves to where their distance reaches the radius, or contact never comes).
  enum class End { kStays, kMoves, kNever, kUndecided };
  auto end = [&](double t, bool at_first, double* moved) {
    if (near(t)) return End::kStays;  // most ends: on a face
    const FootprintGap g = gap();
    if (g.distance <= radius) return End::kStays;
    // Outside reach but not at two corners: only rounding puts an instant of the interval
    // there (its points lie within the grown separating axes).
    if (!g.corner_pair) return End::kUndecided;
    // The two corners' distance over time: |corners + w s| <= radius for s in [s0, s1].
    const double qa = w2.squaredNorm(), qb = g.corners.dot(w2);
    const double qc = g.corners.squaredNorm() - radius * radius;
    const double disc = qb * qb - qa * qc;
    if (qa == 0.0 || !(disc >= 0.0)) return End::kNever;
    const double root = std::sqrt(disc);
    const double s0 = (-qb - root) / qa, s1 = (-qb + root) / qa;
    if (at_first) {
      if (s1 < 0.0) return End::kNever;  // past the corners' disk: moving apart
      const double at = t + std::max(s0, 0.0);
      if (at > last) return End::kNever;
      *moved = at;
      return End::kMoves;
    }
    if (s0 > 0.0) return End::kNever;  // not there yet: contact only after the interval
    const double at = t + std::min(s1, 0.0);
    if (at < first) return End::kNever;
    *moved = at;
    return End::kMoves;
  };
  double moved_first = first, moved_last = last;
  const End head = end(first, true, &moved_first);
  const End tail = end(last, false, &moved_last);
  if (head == End::kUndecided || tail == End::kUndecided) return false;
  // A pocket's disk missed at one end means no contact at all (a line meets a convex set in
  // one piece); the other end must agree, or rounding decided one of them.
  if ((head == End::kNever) != (tail == End::kNever)) return false;
  if (head == End::kNever) {
    *out = TimeInterval{};
    return true;
  }
  if (moved_first > moved_last) return false;
  out->first = std::max(first, widenDown(moved_first));
  out->last = std::min(last, widenUp(moved_last));
  return true;
}

}  // namespace workspace_proximity
