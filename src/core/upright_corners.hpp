#pragma once
// The nearest corner of one rectangle to another (private to the core): shared by the exact
// distance of upright boxes (upright_box_distance.cpp, which defines it) and the contact
// window of rounded upright boxes (contact_window.cpp), which both work on footprints in x-y.

#include <Eigen/Core>

namespace workspace_proximity {
namespace upright {

using Vec2 = Eigen::Vector2d;

// The nearest of a rectangle's four corners (centre `centre`, half-size vectors eu and ev, all
// in self's frame) to self's rectangle [-high, high]: the squared distance, the corner and its
// nearest point on self (clamped to the rectangle).
double nearestCornerTo(const Vec2& high, const Vec2& centre, const Vec2& eu, const Vec2& ev,
                       Vec2* corner, Vec2* on_self);

}  // namespace upright
}  // namespace workspace_proximity
