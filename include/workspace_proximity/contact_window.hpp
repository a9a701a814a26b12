#pragma once
/// The contact-window stage, between the broad phase and the narrow phase: the time interval
/// of [0, horizon] outside which two margin-inflated bodies cannot touch, and what the narrow
/// phase still has to refine inside it. Runs once per pair and cycle.

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace workspace_proximity {

struct ContactWindow {
  /// Step 1, per-axis time of impact: the bodies' rotation-inflated boxes (PairBody::half)
  /// overlap only within this part of [0, horizon] (boxContactInterval). Empty: no contact
  /// within the horizon.
  TimeInterval axis;
  /// Step 2, within `axis`: for two boxes that only translate, the moving separating-axis
  /// interval (movingBoxInterval); otherwise `axis` itself. The narrow phase looks for
  /// contact only here. Empty: no contact within the horizon.
  TimeInterval interval;
  /// `interval` is exactly the contact interval (margin-free translating boxes): nothing is
  /// left to refine.
  bool exact = false;
  /// `interval.last` already is a conservative last contact (translating boxes with margins,
  /// i.e. rounded boxes, which the axis test bounds): only the first contact is refined.
  bool last_known = false;

  bool empty() const { return interval.empty(); }
};

/// Step 1 alone: boxContactInterval() of the bodies' rotation-inflated boxes (PairBody::half,
/// centred on the positions at t = 0, translating at the linear velocities) within
/// [0, horizon].
TimeInterval axisWindow(const PairBody& a, const PairBody& b, double horizon);

/// Step 2 alone: narrows `window` (seconds, the axis window or any part of [0, horizon]) for
/// two bodies (shape, motion, margin and pose now of each are read). Two boxes that only
/// translate get movingBoxInterval() at their poses at t = 0, exact without margins and
/// conservative with them; other pairs keep the window as it is. `axis` of the result is
/// `window`.
ContactWindow refineWindow(const PairBody& a, const PairBody& b, TimeInterval window);

/// Both steps: refineWindow(a, b, axisWindow(a, b, horizon)).
ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon);

}  // namespace workspace_proximity
