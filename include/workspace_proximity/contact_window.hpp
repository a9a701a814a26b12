#pragma once
/// The contact-window stage, between the broad phase and the narrow phase: the time interval
/// of [0, horizon] outside which two margin-inflated bodies cannot touch, and what the narrow
/// phase still has to refine inside it. Runs once per pair and cycle.

#include <cstdint>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/motion_path.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace workspace_proximity {

class PairPieces;

struct ContactWindow {
  /// Step 1, per-axis time of impact: the bodies' rotation-inflated boxes (PairBody::half)
  /// overlap only within this part of [0, horizon] (boxContactInterval). Empty: no contact
  /// within the horizon.
  TimeInterval axis;
  /// Step 2, within `axis`: for two boxes that only translate, the moving separating-axis
  /// interval (movingBoxInterval); otherwise `axis` itself. The narrow phase looks for
  /// contact only here. Empty: no contact within the horizon.
  TimeInterval interval;
  /// `interval` is exactly the contact interval (translating boxes without margins, or
  /// upright ones with margins: roundedUprightInterval()): nothing is left to refine.
  bool exact = false;
  /// `interval.last` already is a conservative last contact (translating boxes with margins,
  /// i.e. rounded boxes, which the axis test bounds): only the first contact is refined.
  bool last_known = false;
  /// Pairs with a piecewise motion or a growing margin (PairBody::piecewise()): the pieces the
  /// window was computed on; the narrow phase walks them. Null for constant-twist pairs.
  const PairPieces* pieces = nullptr;

  bool empty() const { return interval.empty(); }
};

/// One body over one piece of a pair's horizon.
struct PieceBody {
  const PathSegment* segment = nullptr;  ///< the segment the body is in
  GrowthPiece growth;                    ///< its margin growth, in x = t - u0
  double growth_rate = 0.0;              ///< m/s, the largest growth rate over the piece
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< centre at u0, m
  /// The segment's pose at its start when the caller has it (the body's first segment:
  /// PairBody::pose), else null.
  const Eigen::Isometry3d* start_pose = nullptr;

  /// Pose at t (s, within the piece). A segment that does not turn keeps its start pose's
  /// rotation matrix (bit for bit what poseAt builds again from the quaternion: the narrow
  /// phase asks for a pose per distance query, 8 % of a crowd with growing margins).
  Eigen::Isometry3d poseAt(double t) const {
    const BodyMotion& m = segment->motion;
    if (start_pose == nullptr || !isExactlyZero(m.angular_velocity)) return m.poseAt(t - segment->start);
    Eigen::Isometry3d pose = *start_pose;
    pose.translation() = m.position + m.linear_velocity * (t - segment->start);
    return pose;
  }
};

/// A stretch [u0, u1] of the horizon on which each body of a pair keeps one segment of its
/// path and its growth one polynomial: between consecutive merged breakpoints (both bodies'
/// segment starts and the instants their growth caps take over).
struct Piece {
  double u0 = 0.0;
  double u1 = 0.0;
  PieceBody a, b;
};

/// The pieces of [0, horizon] for a pair with a piecewise motion or a growing margin. A body
/// without a path is one segment (its motion, margin and half over the horizon). Holds at most
/// 2 Limits::kMaxSegments + 3 breakpoints in place: building it allocates nothing.
class PairPieces {
 public:
  static constexpr int kMaxPieces = 2 * Limits::kMaxSegments + 2;

  /// `a` and `b` (and what they point to) must outlive the pieces.
  PairPieces(const PairBody& a, const PairBody& b, double horizon);
  PairPieces(const PairPieces&) = delete;
  PairPieces& operator=(const PairPieces&) = delete;

  int size() const { return count_; }
  double horizon() const { return horizon_; }
  Piece piece(int i) const;
  /// The last piece whose start is at or before t (0 for t <= 0).
  int pieceAt(double t) const;
  /// pieceAxisWindow(piece(i)) with growth, `p` being piece(i): remembered for the first
  /// kRemembered pieces, since piecewiseWindow and the narrow phase's forward advancement both
  /// ask (growingAxisInterval is ~14 % of a crowd with growing margins).
  TimeInterval axisWindowOf(int i, const Piece& p) const;
  static constexpr int kRemembered = 4;
  const PairBody& a() const { return *a_; }
  const PairBody& b() const { return *b_; }

 private:
  PieceBody body(const PairBody& body, const PathSegment* segments, int segment,
                 const Eigen::Isometry3d* first_pose, double u0, double u1) const;
  static const Eigen::Isometry3d* firstPose(const PairBody& body, const PathSegment* segments);

  const PairBody* a_;
  const PairBody* b_;
  double horizon_;
  // A body without a path: its one segment over the whole horizon.
  PathSegment own_a_, own_b_;
  const PathSegment* segments_a_;
  const PathSegment* segments_b_;
  // Each body's pose now, when it is its first segment's pose at its start (PieceBody::
  // start_pose), else null.
  const Eigen::Isometry3d* first_pose_a_ = nullptr;
  const Eigen::Isometry3d* first_pose_b_ = nullptr;
  // Not initialised (a pair's pieces are built for every pair and cycle): read only where
  // windows_known_ says so.
  mutable double window_first_[kRemembered];
  mutable double window_last_[kRemembered];
  mutable std::uint32_t windows_known_ = 0;  // bit i: piece i's window is remembered
  int count_ = 0;
  double breaks_[kMaxPieces + 1];
  std::int16_t segment_a_[kMaxPieces];
  std::int16_t segment_b_[kMaxPieces];
};

/// Step 1 on one piece: the per-axis test (growingAxisInterval) of the two bodies' segment
/// boxes (PathSegment::half around the moving centres), each grown by its growth unless
/// `with_growth` is false; intersected over the axes. Seconds after the prediction instant,
/// within [u0, u1]; empty: the boxes do not meet on this piece.
TimeInterval pieceAxisWindow(const Piece& piece, bool with_growth = true);

/// Steps 1 and 2 for a pair with a piecewise motion or a growing margin: the hull of every
/// piece's axis window (with growth); `pieces` is set, `exact` and `last_known` are false.
ContactWindow piecewiseWindow(const PairPieces& pieces);

/// Step 1 alone: boxContactInterval() of the bodies' rotation-inflated boxes (PairBody::half,
/// centred on the positions at t = 0, translating at the linear velocities) within
/// [0, horizon].
TimeInterval axisWindow(const PairBody& a, const PairBody& b, double horizon);

/// Step 2 alone: narrows `window` (seconds, the axis window or any part of [0, horizon]) for
/// two bodies (shape, motion, margin and pose now of each are read). Two boxes that only
/// translate get movingBoxInterval() at their poses at t = 0, exact without margins and
/// conservative with them, unless both are upright and have margins: then
/// roundedUprightInterval() makes it exact (it leaves the rims of boxes whose heights part to
/// the former). Other pairs keep the window as it is. `axis` of the result is `window`.
ContactWindow refineWindow(const PairBody& a, const PairBody& b, TimeInterval window);

/// Both steps: refineWindow(a, b, axisWindow(a, b, horizon)).
ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon);

/// Exact contact interval of two upright boxes that only translate (constant velocities, m/s)
/// and are grown by a ball whose radius `inflation` (m, > 0) is the sum of their margins:
/// the instants within `window` (s) at which the boxes are at most `inflation` apart.
///
/// First the separating axes of two vertical prisms (the four footprint normals and z), each
/// grown by `inflation`, as movingBoxInterval() does: that interval holds every contact and is
/// exact where contact begins or ends on a face of a footprint. Where it begins or ends at two
/// corners (the grown footprints' rounded corners, which the axes square off) the boxes are
/// further apart than `inflation` there, and that end moves to where the two corners come
/// within `inflation` (one quadratic), or the interval is empty when they never do.
///
/// Returns false, leaving *out alone, when the footprints do not decide it: the heights do
/// not overlap throughout (contact could begin at a rounded rim), non-finite input, or
/// rounding left the two ends inconsistent. The caller then refines another way. Both ends
/// are widened outward by a nanometre of distance and a few ulps of time, so rounding never
/// narrows the interval.
bool roundedUprightInterval(const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                            const Eigen::Vector3d& velocity_a, const Eigen::Isometry3d& pose_b,
                            const Eigen::Vector3d& half_b, const Eigen::Vector3d& velocity_b,
                            double inflation, TimeInterval window, TimeInterval* out);

}  // namespace workspace_proximity
