#pragma once
/// Conservative bounds of a moving body over the prediction horizon.

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// Half extents (m) of an axis-aligned box centred on the body centre that contains the shape
/// in every orientation it takes over [0, horizon], plus the margin.
///
/// Without rotation the box is the exact world bound of the shape. With rotation, the bound
/// used: each column of the rotation matrix moves by at most the chord
/// 2 sin(theta / 2) of the largest rotation angle theta = min(|omega| * horizon, pi), so the
/// world half extent on axis k grows by at most chord * sum(local half extents); it never
/// exceeds the bounding-sphere radius. Exact for pure translation.
Eigen::Vector3d rotationHalfExtents(const Shape& shape, const BodyMotion& motion, double margin,
                                    double horizon);

/// Axis-aligned box (world, m) that contains the body (with margin) at every t in [0, horizon].
/// It is the union of the rotation-inflated box at t = 0 and at t = horizon (the centre
/// moves on a straight line, so the union of the two end boxes covers every box in between).
Aabb sweptBounds(const Shape& shape, const BodyMotion& motion, double margin, double horizon);

}  // namespace workspace_proximity
