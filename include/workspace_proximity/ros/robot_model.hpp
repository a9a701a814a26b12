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

#include "workspace_proximity/ros/monitor_params.hpp"

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

/// A box: `pose` maps box coordinates to the frame of the points it bounds (translation =
/// centre, columns of the rotation = the box's axes); it spans [-half_extents, half_extents].
struct OrientedBox {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  ///< m, each >= 0
  double volume() const { return 8.0 * half_extents.prod(); }
};

/// Oriented bounding box of `points` (finite; at least one column).
/// Containment: the extents are the exact minima and maxima of all the points along the
/// box's axes, so every point is inside up to the rounding of one dot product (~1e-16
/// relative; the tests check 1e-9 m).
/// Tightness: candidate frames are the points' own frame, the principal axes of the convex
/// hull's vertices and of its surface, and the normals of the hull's 64 largest face
/// directions; each is refined by turning it about one axis at a time to the minimum-area
/// rectangle of the projection on the other two (rotating calipers), until the volume stops
/// shrinking; the smallest wins. Hence it is never larger than the box of the points in their
/// own frame; it is the exact minimum for boxes and for prisms whose optimum is flush with a
/// face (checked to 1e-9 in test_robot_model); on the tests' 41 random clouds (6 to 3 000
/// points) it was never larger than the best of 20 000 sampled orientations (0.75 % to 0.1 %
/// smaller at worst). Above 1 024 points the search sees only the extreme points along 512
/// directions (the hull through qhull, by geometric_shapes); candidates are then judged and
/// the extents taken on every point (a 100 000-point Gaussian cloud came out 1.2 % larger
/// than with the full search).
/// Cost (start-up only; one core of a shared, loaded 2-core EPYC VM): 60-150 ms when all of
/// 1 000 points are hull vertices, 0.3-0.6 s for 100 000; 3-9 ms for a 1 000-point cloud.
OrientedBox orientedBoundingBox(const Eigen::Matrix3Xd& points);

}  // namespace workspace_proximity
