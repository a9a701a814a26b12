#include "workspace_proximity/contact_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

PieceBody PairPieces::body(const PairBody& body, const PathSegment* segments, int segment, double u0,
                           double u1) const {
  PieceBody p;
  p.segment = &segments[segment];
  p.centre = p.segment->centreAt(u0);
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
  p.a = body(*a_, segments_a_, segment_a_[i], p.u0, p.u1);
  p.b = body(*b_, segments_b_, segment_b_[i], p.u0, p.u1);
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

ContactWindow piecewiseWindow(const PairPieces& pieces) {
  ContactWindow w;
  w.pieces = &pieces;
  TimeInterval hull;  // empty
  bool any = false;
  for (int i = 0; i < pieces.size(); ++i) {
    const TimeInterval piece = pieceAxisWindow(pieces.piece(i));
    if (piece.empty()) continue;
    if (!any) hull.first = piece.first;
    hull.last = piece.last;
    any = true;
  }
  w.axis = hull;
  w.interval = hull;
  return w;
}

}  // namespace workspace_proximity
