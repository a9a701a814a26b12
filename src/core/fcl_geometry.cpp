#include "fcl_geometry.hpp"

#include <stdexcept>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>

namespace workspace_proximity {

std::unique_ptr<fcl::CollisionGeometryd> makeFclGeometry(const Shape& shape) {
  if (!shape.valid()) throw std::invalid_argument("makeFclGeometry: invalid shape");
  switch (shape.type) {
    case ShapeType::kBox:
      return std::make_unique<fcl::Boxd>(2.0 * shape.half_extents);
    case ShapeType::kSphere:
      return std::make_unique<fcl::Sphered>(shape.radius);
    case ShapeType::kCylinder:
      return std::make_unique<fcl::Cylinderd>(shape.radius, shape.length);
    case ShapeType::kCapsule:
      if (shape.length == 0.0) return std::make_unique<fcl::Sphered>(shape.radius);
      return std::make_unique<fcl::Capsuled>(shape.radius, shape.length);
  }
  throw std::invalid_argument("makeFclGeometry: unknown shape type");
}

}  // namespace workspace_proximity
