#include "workspace_proximity/replay/robot_from_file.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include <ros/package.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace workspace_proximity {
namespace {

// "package://pkg/path" and "file:///path" to a local path; empty when unresolvable (the
// node's rule, robot_description.cpp).
std::string resolveMesh(const std::string& url) {
  const std::string package_prefix = "package://";
  const std::string file_prefix = "file://";
  if (url.compare(0, package_prefix.size(), package_prefix) == 0) {
    const std::string rest = url.substr(package_prefix.size());
    const auto slash = rest.find('/');
    if (slash == std::string::npos) return std::string();
    const std::string root = ros::package::getPath(rest.substr(0, slash));
    return root.empty() ? std::string() : root + rest.substr(slash);
  }
  if (url.compare(0, file_prefix.size(), file_prefix) == 0) return url.substr(file_prefix.size());
  return url;
}

}  // namespace

std::vector<RobotBodySpec> robotBodiesFromFile(const std::string& urdf_path,
                                               const MonitorParams& params,
                                               std::vector<std::string>* warnings) {
  std::vector<RobotBodySpec> specs = params.robot_bodies;
  if (params.use_robot_description && !urdf_path.empty()) {
    std::ifstream in(urdf_path);
    if (!in) throw std::runtime_error(urdf_path + ": cannot read the URDF file");
    std::stringstream xml;
    xml << in.rdbuf();
    std::vector<std::string> urdf_warnings;
    std::vector<RobotBodySpec> from_urdf;
    try {
      // The one call of the URDF model in the replay.
      from_urdf = bodiesFromUrdf(xml.str(), resolveMesh, &urdf_warnings);
    } catch (const std::exception& e) {
      throw std::runtime_error(urdf_path + ": " + e.what());
    }
    for (const std::string& w : urdf_warnings) warnings->push_back("URDF " + w);
    specs.insert(specs.end(), from_urdf.begin(), from_urdf.end());
  }
  std::vector<RobotBodySpec> unique;
  std::unordered_set<std::string> names;
  for (const RobotBodySpec& spec : specs) {
    if (!names.insert(spec.name).second) {
      warnings->push_back("robot body '" + spec.name + "' declared twice; the first is used");
      continue;
    }
    unique.push_back(spec);
  }
  return unique;
}

}  // namespace workspace_proximity
