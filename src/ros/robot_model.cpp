#include "workspace_proximity/ros/robot_model.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <urdf/model.h>

namespace workspace_proximity {
namespace {

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

bool endsWithNoCase(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) {
      return false;
    }
  }
  return true;
}

// Builds the body for one collision geometry; returns false with a reason when unusable.
bool makeBody(const urdf::Geometry& geometry, const MeshResolver& resolve, RobotBodySpec* body,
              std::string* why) {
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      body->shape = Shape::box(0.5 * Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z));
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(geometry);
      body->shape = Shape::cylinder(c.radius, c.length);
      break;
    }
    case urdf::Geometry::SPHERE:
      body->shape = Shape::sphere(static_cast<const urdf::Sphere&>(geometry).radius);
      break;
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      if (!endsWithNoCase(mesh.filename, ".stl")) {
        *why = "mesh '" + mesh.filename + "' is not STL (only STL meshes can be bounded)";
        return false;
      }
      const std::string path = resolve ? resolve(mesh.filename) : std::string();
      Eigen::Vector3d lo, hi;
      if (path.empty() || !stlBounds(path, &lo, &hi)) {
        *why = "mesh '" + mesh.filename + "' cannot be read";
        return false;
      }
      const Eigen::Vector3d scale(mesh.scale.x, mesh.scale.y, mesh.scale.z);
      const Eigen::Vector3d a = lo.cwiseProduct(scale), b = hi.cwiseProduct(scale);
      // A box around the scaled vertices, centred where they are.
      body->shape = Shape::box(0.5 * (a - b).cwiseAbs());
      Eigen::Isometry3d centre = Eigen::Isometry3d::Identity();
      centre.translation() = 0.5 * (a + b);
      body->offset = body->offset * centre;
      break;
    }
    default:
      *why = "unknown geometry type";
      return false;
  }
  if (!body->shape.valid()) {
    *why = "zero or invalid size";
    return false;
  }
  return true;
}

}  // namespace

bool stlBounds(const std::string& path, Eigen::Vector3d* lower, Eigen::Vector3d* upper) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  int vertices = 0;
  auto add = [&](double x, double y, double z) {
    const Eigen::Vector3d v(x, y, z);
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
    ++vertices;
  };
  // Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. An ASCII file can start
  // with "solid" too, so the size decides.
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50ull * n) {
      for (std::uint32_t t = 0; t < n; ++t) {
        const char* tri = data.data() + 84 + 50ull * t + 12;  // skip the normal
        for (int k = 0; k < 3; ++k) {
          float v[3];
          std::memcpy(v, tri + 12 * k, 12);
          add(v[0], v[1], v[2]);
        }
      }
      if (vertices == 0 || !lo.allFinite() || !hi.allFinite()) return false;
      *lower = lo;
      *upper = hi;
      return true;
    }
  }
  std::istringstream text(data);
  std::string word;
  while (text >> word) {
    if (word != "vertex") continue;
    double x, y, z;
    if (!(text >> x >> y >> z)) return false;
    add(x, y, z);
  }
  if (vertices == 0 || !lo.allFinite() || !hi.allFinite()) return false;
  *lower = lo;
  *upper = hi;
  return true;
}

std::vector<RobotBodySpec> bodiesFromUrdf(const std::string& urdf_xml, const MeshResolver& resolve,
                                          std::vector<std::string>* warnings) {
  urdf::Model model;
  if (!model.initString(urdf_xml)) throw std::runtime_error("robot_description: URDF does not parse");
  std::vector<urdf::LinkSharedPtr> links;
  model.getLinks(links);
  std::vector<RobotBodySpec> bodies;
  for (const urdf::LinkSharedPtr& link : links) {
    std::vector<urdf::CollisionSharedPtr> elements = link->collision_array;
    if (elements.empty() && link->collision) elements.push_back(link->collision);
    for (std::size_t i = 0; i < elements.size(); ++i) {
      const urdf::CollisionSharedPtr& c = elements[i];
      if (!c || !c->geometry) continue;
      RobotBodySpec body;
      body.name = elements.size() == 1 ? link->name : link->name + "/" + std::to_string(i);
      body.frame = link->name;
      body.offset = toIsometry(c->origin);
      std::string why;
      if (!makeBody(*c->geometry, resolve, &body, &why)) {
        if (warnings) warnings->push_back("link '" + link->name + "': " + why + "; skipped");
        continue;
      }
      bodies.push_back(body);
    }
  }
  return bodies;
}

}  // namespace workspace_proximity
