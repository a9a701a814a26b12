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

/// The margin of a track of this label, m: margin + position_error.
double trackMargin(const LabelSettings& label);

/// The growth of a track of this label at a prediction instant `age` seconds away from its
/// measurement stamp (either side: the uncertainty grows with the time the track is
/// extrapolated over), moving at `speed` m/s (|v|, for the speed cap). No growth when the label
/// has neither velocity_error nor max_accel. Always MarginGrowth::valid() for validated
/// settings and finite inputs.
MarginGrowth trackGrowth(const LabelSettings& label, double speed, double age);

}  // namespace workspace_proximity
