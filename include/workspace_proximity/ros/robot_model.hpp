#pragma once
/// Robot bodies from a URDF's collision elements.

#include <functional>
#include <string>
#include <vector>

#include "workspace_proximity/monitor/monitor_params.hpp"

namespace workspace_proximity {

/// Turns a mesh URL ("package://pkg/file.stl", "file:///abs/file.stl") into a local path;
/// returns an empty string when it cannot.
using MeshResolver = std::function<std::string(const std::string& url)>;

/// One body per collision element: boxes, cylinders and spheres as they are; meshes bounded
/// by the box of their vertices (STL, ASCII or binary). A link with one collision element
/// gives a body named after the link; with several, "<link>/<index>". Elements that cannot
/// be used (unknown mesh format, unreadable file, zero size) are skipped with a line in
/// `warnings`. Throws std::runtime_error when the URDF does not parse.
std::vector<RobotBodySpec> bodiesFromUrdf(const std::string& urdf_xml, const MeshResolver& resolve,
                                          std::vector<std::string>* warnings);

/// Axis-aligned bounds (m, in the mesh's frame) of the vertices of an STL file.
/// Returns false when the file cannot be read or is not STL.
bool stlBounds(const std::string& path, Eigen::Vector3d* lower, Eigen::Vector3d* upper);

}  // namespace workspace_proximity
