#include "workspace_proximity/ros/robot_model.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <geometric_shapes/bodies.h>
#include <geometric_shapes/mesh_operations.h>
#include <geometric_shapes/shapes.h>
#include <resource_retriever/retriever.h>
#include <tinyxml2.h>
#include <urdf/model.h>

namespace workspace_proximity {
namespace {

// ---------------------------------------------------------------------------
// Mesh loading.

std::string lowerExtension(const std::string& url) {
  const std::size_t slash = url.find_last_of('/');
  const std::size_t dot = url.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return std::string();
  std::string ext = url.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The length of one unit of a COLLADA document in metres (<COLLADA><asset><unit meter>),
// 1 when it says nothing usable.
double colladaUnit(const char* data, std::size_t size) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(data, size) != tinyxml2::XML_SUCCESS) return 1.0;
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "COLLADA") return 1.0;
  const tinyxml2::XMLElement* asset = root->FirstChildElement("asset");
  const tinyxml2::XMLElement* unit = asset ? asset->FirstChildElement("unit") : nullptr;
  double meter = 1.0;
  if (!unit || unit->QueryDoubleAttribute("meter", &meter) != tinyxml2::XML_SUCCESS) return 1.0;
  return std::isfinite(meter) && meter > 0.0 ? meter : 1.0;
}

// Why geometric_shapes made no mesh of the data: asked of assimp directly, which
// geometric_shapes does not pass on.
std::string assimpCause(const char* data, std::size_t size, const std::string& ext,
                        const std::string& url) {
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFileFromMemory(data, size, aiProcess_Triangulate | aiProcess_SortByPType, ext.c_str());
  if (!scene) {
    // assimp names the in-memory file "$$$___magic___$$$.<ext>"; say which file it was.
    std::string error = importer.GetErrorString();
    const std::string magic = std::string(AI_MEMORYIO_MAGIC_FILENAME) + "." + ext;
    const std::size_t at = error.find(magic);
    if (at != std::string::npos) error.replace(at, magic.size(), url.substr(url.find_last_of('/') + 1));
    return "not a mesh assimp can read (" + error + ")";
  }
  if (!scene->HasMeshes()) return "holds no mesh";
  return "holds no triangles";
}

// ---------------------------------------------------------------------------
// URDF.

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

// Builds the body for one collision geometry; returns false with a reason when unusable.
bool makeBody(const urdf::Geometry& geometry, RobotBodySpec* body, std::string* why) {
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
      Eigen::Matrix3Xd vertices;
      if (!loadMeshVertices(mesh.filename, Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z),
                            &vertices, why)) {
        return false;
      }
      const OrientedBox box = orientedBoundingBox(vertices);
      if (!(box.half_extents.maxCoeff() >= Limits::kMinSize)) {
        *why = "mesh '" + mesh.filename + "': zero size (after scaling it spans less than " +
               number(2.0 * Limits::kMinSize) + " m on every axis)";
        return false;
      }
      // A flat or thin mesh (a panel) keeps its place: at least the smallest size a shape may
      // have, which only adds room around it.
      body->shape = Shape::box(box.half_extents.cwiseMax(Limits::kMinSize));
      body->offset = body->offset * box.pose;
      if (!body->shape.valid()) {
        *why = "mesh '" + mesh.filename + "': " + number(2.0 * box.half_extents.maxCoeff()) +
               " m long, more than the largest shape (" + number(2.0 * Limits::kMaxSize) +
               " m; wrong units or scale?)";
        return false;
      }
      return true;
    }
    default:
      *why = "unknown geometry type " + std::to_string(static_cast<int>(geometry.type));
      return false;
  }
  if (!body->shape.valid()) {
    const Shape& s = body->shape;
    *why = s.type == ShapeType::kBox
               ? "box " + number(2 * s.half_extents.x()) + " x " + number(2 * s.half_extents.y()) + " x " +
                     number(2 * s.half_extents.z()) + " m"
               : s.type == ShapeType::kSphere ? "sphere of radius " + number(s.radius) + " m"
                                              : "cylinder of radius " + number(s.radius) + " m, length " +
                                                    number(s.length) + " m";
    *why += ": zero or invalid size (each half size, radius and length within [" +
            number(Limits::kMinSize) + ", " + number(Limits::kMaxSize) + "] m)";
    return false;
  }
  return true;
}

}  // namespace

bool loadMeshVertices(const std::string& url, const Eigen::Vector3d& scale,
                      Eigen::Matrix3Xd* vertices, std::string* why) {
  const std::string what = "mesh '" + url + "': ";
  try {
    std::string resolved = url;
    if (url.find("://") == std::string::npos) {
      if (url.empty() || url[0] != '/') {
        *why = what + "a relative path (the URDF needs package://, file:// or an absolute path)";
        return false;
      }
      resolved = "file://" + url;
    }
    if (!scale.allFinite()) {
      *why = what + "non-finite scale";
      return false;
    }
    resource_retriever::Retriever retriever;
    resource_retriever::MemoryResource resource;
    try {
      resource = retriever.get(resolved);
    } catch (const resource_retriever::Exception& e) {
      *why = what + "cannot be retrieved (" + e.what() + ")";
      return false;
    }
    if (resource.size == 0 || !resource.data) {
      *why = what + "the file is empty";
      return false;
    }
    const char* data = reinterpret_cast<const char*>(resource.data.get());
    const std::string ext = lowerExtension(resolved);
    const double unit = ext == "dae" ? colladaUnit(data, resource.size) : 1.0;
    // geometric_shapes takes assimp's format hint from the name's extension.
    const std::unique_ptr<shapes::Mesh> mesh(
        shapes::createMeshFromBinary(data, resource.size, unit * scale, resolved));
    if (!mesh) {
      *why = what + assimpCause(data, resource.size, ext, url);
      return false;
    }
    if (mesh->vertex_count == 0 || mesh->triangle_count == 0) {
      *why = what + "holds no triangles";
      return false;
    }
    vertices->resize(3, mesh->vertex_count);
    for (unsigned int i = 0; i < mesh->vertex_count; ++i) {
      for (int d = 0; d < 3; ++d) (*vertices)(d, i) = mesh->vertices[3 * i + d];
    }
    if (!vertices->allFinite()) {
      *why = what + "non-finite vertex coordinates";
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    *why = what + "cannot be loaded (" + e.what() + ")";
    return false;
  }
}

UrdfBodies bodiesFromUrdf(const std::string& urdf_xml) {
  urdf::Model model;
  if (!model.initString(urdf_xml)) throw std::runtime_error("robot_description: URDF does not parse");
  std::vector<urdf::LinkSharedPtr> links;
  model.getLinks(links);
  UrdfBodies result;
  for (const urdf::LinkSharedPtr& link : links) {
    std::vector<urdf::CollisionSharedPtr> elements = link->collision_array;
    if (elements.empty() && link->collision) elements.push_back(link->collision);
    for (std::size_t i = 0; i < elements.size(); ++i) {
      const urdf::CollisionSharedPtr& c = elements[i];
      RobotBodySpec body;
      body.name = elements.size() == 1 ? link->name : link->name + "/" + std::to_string(i);
      body.frame = link->name;
      std::string why;
      bool made = false;
      if (!c || !c->geometry) {
        why = "collision element without geometry";
      } else {
        try {
          body.offset = toIsometry(c->origin);
          made = makeBody(*c->geometry, &body, &why);
        } catch (const std::exception& e) {
          why = std::string("cannot be modelled (") + e.what() + ")";
        }
      }
      if (made) {
        result.bodies.push_back(body);
      } else {
        result.unmodelled.push_back(UnmodelledElement{link->name, i, body.name, why});
      }
    }
  }
  return result;
}

}  // namespace workspace_proximity
