#include "workspace_proximity/contact_window.hpp"

namespace workspace_proximity {
namespace {

// Trackers report most objects as boxes that only translate: they have a closed form.
bool translatingBox(const Shape& shape, const BodyMotion& motion) {
  return shape.type == ShapeType::kBox && motion.angular_velocity.isZero(0.0) &&
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
  // The moving separating-axis test: exact without margins, and with them (rounded boxes) an
  // interval that contains every contact, whose exit time stands as the last contact.
  const double margins = a.margin + b.margin;
  Eigen::Isometry3d scratch_a, scratch_b;
  w.interval = movingBoxInterval(a.poseNow(&scratch_a), a.shape->half_extents,
                                 a.motion->linear_velocity, b.poseNow(&scratch_b),
                                 b.shape->half_extents, b.motion->linear_velocity, margins, window);
  w.exact = margins == 0.0;
  w.last_known = true;
  return w;
}

ContactWindow contactWindow(const PairBody& a, const PairBody& b, double horizon) {
  return refineWindow(a, b, axisWindow(a, b, horizon));
}

}  // namespace workspace_proximity
