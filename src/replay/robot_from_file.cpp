#include "workspace_proximity/replay/robot_from_file.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace workspace_proximity {

RobotDescription robotBodiesFromFile(const std::string& urdf_path, const MonitorParams& params,
                                     std::vector<std::string>* warnings) {
  std::string xml;
  if (params.use_robot_description && !urdf_path.empty()) {
    std::ifstream in(urdf_path);
    if (!in) throw std::runtime_error(urdf_path + ": cannot read the URDF file");
    std::stringstream text;
    text << in.rdbuf();
    xml = text.str();
  }
  try {
    return robotDescription(xml.empty() ? nullptr : &xml, params, warnings);
  } catch (const std::exception& e) {
    throw std::runtime_error(urdf_path + ": " + e.what());
  }
}

}  // namespace workspace_proximity
