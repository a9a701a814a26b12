#pragma once
/// A tracked object's bounded uncertainty, from its label's settings: the margin it is given
/// and how that margin grows with time (the core's MarginGrowth). ROS-free.
///
/// An object measured at c with velocity v, whose velocity is known to within e, whose
/// acceleration is at most a and whose speed is at most v_max, is s seconds after the
/// measurement within
///   R(s) = min(e s + a s^2 / 2, (v_max + |v|) s)
/// of c + v s (the first term: velocity error plus the displacement of any acceleration; the
/// second: it cannot leave the nominal point faster than v_max + |v|). Adding position_error
/// and R(s) to the margin makes every motion within those bounds a motion inside the grown
/// shape, so a contact predicted for the grown shape is never later than the real one.

#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/motion_path.hpp"

namespace workspace_proximity {

/// A track's own uncertainty, as its tracker reported it (BoxObservation's fields). The
/// label's settings stay a floor: the effective error is the larger of the two.
struct TrackErrors {
  double position_error = 0.0;  ///< m, 3 sigma; 0: the label's
  double velocity_error = 0.0;  ///< m/s, 3 sigma; 0: the label's
  /// false: the tracker has no velocity for it yet. Its nominal velocity is then 0 and it
  /// grows at R(s) = v_u s, v_u = unknownVelocitySpeed(label) (every motion no faster than
  /// that stays inside), whatever the label's other growth terms say.
  bool velocity_known = true;
};

/// m/s, v_u: how fast a track of this label whose velocity is unknown may move: the label's
/// max_speed, or when it states none, the larger of its ssm_min_speed and
/// kUnknownVelocityFallbackSpeed (a label without max_speed says nothing about its speed; the
/// fallback is ISO 13855's hand speed, and no stated model: the monitor is DEGRADED while such
/// a track lives, TrackTable::unboundedLines).
double unknownVelocitySpeed(const LabelSettings& label);
constexpr double kUnknownVelocityFallbackSpeed = 2.0;  ///< m/s

/// The margin of a track of this label, m: margin + max(label's position_error,
/// `position_error`, the track's own).
double trackMargin(const LabelSettings& label, double position_error = 0.0);

/// The growth of a track of this label at a prediction instant `age` seconds away from its
/// measurement stamp (either side: the uncertainty grows with the time the track is
/// extrapolated over), moving at `speed` m/s (|v|, for the speed cap), with its own errors
/// `own`. Velocity known: e = max(label's velocity_error, own), a = max_accel, cap
/// max_speed + |v|; no growth when e and a are both 0. Velocity unknown: e = cap = v_u, a = 0,
/// so R(s) = v_u s. Always MarginGrowth::valid() for validated settings and finite inputs.
MarginGrowth trackGrowth(const LabelSettings& label, double speed, double age,
                         const TrackErrors& own = TrackErrors());

}  // namespace workspace_proximity
