#include "workspace_proximity/rules/kinematic_model.hpp"

namespace workspace_proximity {

int KinematicModel::jointIndex(const std::string& name) const {
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    if (joints_[j].name == name) return static_cast<int>(j);
  }
  return -1;
}

int KinematicModel::linkIndex(const std::string& name) const {
  for (std::size_t l = 0; l < links_.size(); ++l) {
    if (links_[l].name == name) return static_cast<int>(l);
  }
  return -1;
}

}  // namespace workspace_proximity
