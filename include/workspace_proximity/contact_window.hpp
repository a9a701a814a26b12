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

/// Step 2 alone: narrows `window` (seconds, within [0, horizon]) for two bodies whose margins
/// add up to `margins` (m). Two boxes that only translate get movingBoxInterval() at their
/// poses at t = 0, exact without margins and conservative with them; other pairs keep the
/// window as it is. `axis` of the result is `window`.
ContactWindow refineWindow(const Shape& shape_a, const BodyMotion& motion_a,
                           const Shape& shape_b, const BodyMotion& motion_b, double margins,
                           TimeInterval window);

/// Both steps for two bodies (shape, motion, margin and half extents of each are read).
ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon);

}  // namespace workspace_proximity
