#pragma once
/// RViz markers for the bodies, their swept volumes, predicted contacts and velocities.

#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/ContactEventArray.h>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// What the markers show of one body this cycle (fixed frame).
struct MarkerBody {
  std::string id;
  bool robot = false;
  Shape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< m/s
  Aabb swept;
  int level = -1;  ///< worst ContactEvent level involving it, -1 for none
};

/// Builds one MarkerArray per cycle. Namespaces: "bodies", "swept", "velocity" (one marker
/// per body, id stable for the body's life), "nearest" and "ttc_text" (one per predicted
/// pair). Markers that existed last cycle but not now are sent with action DELETE; every
/// marker has `lifetime` so everything vanishes if the node stops.
class MarkerBuilder {
 public:
  MarkerBuilder(const std::string& frame, double lifetime);

  void build(const std::vector<MarkerBody>& bodies, const ContactEventArray& events,
             const ros::Time& stamp, visualization_msgs::MarkerArray* out);

 private:
  int idFor(const std::string& key);
  visualization_msgs::Marker base(const std::string& ns, const std::string& key,
                                  const ros::Time& stamp);

  std::string frame_;
  ros::Duration lifetime_;
  std::unordered_map<std::string, int> ids_;  // "<ns>|<key>" -> marker id
  std::unordered_map<int, std::string> keys_; // marker id -> "<ns>|<key>"
  std::vector<int> free_ids_;                 // ids of deleted markers, reused
  int next_id_ = 0;
  std::set<std::pair<std::string, int>> published_;
  std::set<std::pair<std::string, int>> current_;
};

}  // namespace workspace_proximity
