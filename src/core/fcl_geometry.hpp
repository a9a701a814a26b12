#pragma once
/// FCL geometry for the core's shapes: what the narrow phase's private cache holds. This
/// header is not installed; no public header names an FCL type.

#include <memory>

#include <fcl/geometry/collision_geometry.h>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// FCL geometry of a shape. Throws std::invalid_argument unless shape.valid(). FCL's box takes
/// full sides; its capsule's lz is the segment between the hemisphere centres, like
/// Shape::length. A zero-length capsule becomes a sphere: FCL 0.7's capsule code trips its
/// own asserts (abort) on it against cylinders (found by fuzzing).
std::unique_ptr<fcl::CollisionGeometryd> makeFclGeometry(const Shape& shape);

}  // namespace workspace_proximity
