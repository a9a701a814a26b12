#pragma once
/// Robot bodies from a URDF's collision elements: primitives as they are, meshes (loaded with
/// geometric_shapes and resource_retriever) bounded by a tight oriented box. A collision
/// element that cannot be modelled is never dropped: it is returned, with the reason, next
/// to the bodies.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/ros/oriented_box.hpp"

namespace workspace_proximity {

/// A URDF collision element that gives no body.
struct UnmodelledElement {
  std::string link;       ///< URDF link name (its tf frame)
  std::size_t index = 0;  ///< position among the link's <collision> elements, from 0
  std::string body;       ///< the body id it would have had ("<link>" or "<link>/<index>")
  /// Why, for a person reading the log: for a mesh it names the file and the cause, e.g.
  /// "mesh 'package://arm/meshes/wrist.stl': cannot be retrieved (...Couldn't open file ...)".
  std::string reason;
};

/// Every collision element of a URDF, each in exactly one of the two lists.
struct UrdfBodies {
  std::vector<RobotBodySpec> bodies;
  std::vector<UnmodelledElement> unmodelled;
};

/// One body per collision element, named after the link when the link has one collision
/// element and "<link>/<index>" when it has several; `frame` is the link, `offset` the
/// collision origin (times the mesh's box pose for meshes).
/// - box, cylinder, sphere: as they are.
/// - mesh (any format assimp reads: STL ASCII and binary, COLLADA .dae, OBJ, ...; URLs
///   "package://", "file://", or an absolute path): the URDF `scale` applied per axis, then
///   bounded by orientedBoundingBox() and modelled as that box. COLLADA files: the root
///   <asset><unit meter="..."> is applied, as rviz does (geometric_shapes alone ignores it).
///   A flat or thin mesh gets at least Limits::kMinSize half extent on each axis.
/// Unmodelled (in `unmodelled`, never thrown): missing or unreadable file, a file that is no
/// mesh or holds no triangles, non-finite vertices, zero size (every half extent below
/// Limits::kMinSize, or a primitive outside the Shape limits), unknown geometry.
/// Throws std::runtime_error only when the URDF itself does not parse.
UrdfBodies bodiesFromUrdf(const std::string& urdf_xml);

/// Loads the vertices of the mesh at `url` (as bodiesFromUrdf() does) with `scale` applied
/// per axis, in metres in the mesh's frame, one vertex per column. Returns false with the
/// cause in `why` (starting with "mesh '<url>': ") when the mesh cannot be used; never throws.
bool loadMeshVertices(const std::string& url, const Eigen::Vector3d& scale,
                      Eigen::Matrix3Xd* vertices, std::string* why);



}  // namespace workspace_proximity
