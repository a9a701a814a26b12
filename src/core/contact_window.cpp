#include "workspace_proximity/contact_window.hpp"

namespace workspace_proximity {
namespace {

// Trackers report most objects as boxes that only translate: they have a closed form.
bool translatingBox(const Shape& shape, const BodyMotion& motion) {
  return shape.type == ShapeType::kBox && motion.angular_velocity.isZero(0.0) &&
         motion.linear_velocity.allFinite();
}

}  // namespace

ContactWindow refineWindow(const Shape& shape_a, const BodyMotion& motion_a,
                           const Shape& shape_b, const BodyMotion& motion_b, double margins,
                           TimeInterval window) {
  ContactWindow w;
  w.axis = window;
  w.interval = window;
  if (window.empty() || !translatingBox(shape_a, motion_a) || !translatingBox(shape_b, motion_b)) {
    return w;
  }
  // The moving separating-axis test: exact without margins, and with them (rounded boxes) an
  // interval that contains every contact, whose exit time stands as the last contact.
  w.interval = movingBoxInterval(motion_a.poseAt(0.0), shape_a.half_extents,
                                 motion_a.linear_velocity, motion_b.poseAt(0.0),
                                 shape_b.half_extents, motion_b.linear_velocity, margins, window);
  w.exact = margins == 0.0;
  w.last_known = true;
  return w;
}

ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon) {
  const TimeInterval axis =
      boxContactInterval(a.motion->position, a.half, a.motion->linear_velocity,
                         b.motion->position, b.half, b.motion->linear_velocity, horizon);
  if (axis.empty()) {
    ContactWindow none;
    none.axis = none.interval = axis;
    return none;
  }
  return refineWindow(*a.shape, *a.motion, *b.shape, *b.motion, a.margin + b.margin, axis);
}

}  // namespace workspace_proximity
