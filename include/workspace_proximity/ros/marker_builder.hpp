#pragma once
/// RViz markers for the bodies, their swept volumes, predicted contacts and velocities.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/ContactEventArray.h>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"
#include "workspace_proximity/pair_table.hpp"

namespace workspace_proximity {

/// What the markers show of one body this cycle (fixed frame).
struct MarkerBody {
  /// Small non-negative integer naming the body for its whole life (the world's body slot,
  /// BodyHandle::index); it is the body's marker id. A slot reused by a later body reuses
  /// the id, which simply redraws it.
  std::int32_t slot = 0;
  bool robot = false;
  Shape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< m/s
  Aabb swept;
  int level = -1;  ///< worst ContactEvent level involving it, -1 for none
};

/// Builds one MarkerArray per cycle. Namespaces: "bodies", "swept", "velocity" (one marker
/// per body, id = its slot, stable for the body's life), "nearest" and "ttc_text" (one per
/// predicted pair, id stable for the pair's life). Markers that existed last cycle but not
/// now are sent with action DELETE; every marker has `lifetime` so everything vanishes if the
/// node stops. Bookkeeping is in flat arrays and an open-addressing pair table; the output
/// array is rewritten in place, so steady cycles allocate (almost) nothing.
class MarkerBuilder {
 public:
  MarkerBuilder(const std::string& frame, double lifetime);

  /// `event_slots[i]` are the slots of the two bodies of `events.events[i]`.
  void build(const std::vector<MarkerBody>& bodies, const ContactEventArray& events,
             const std::vector<std::pair<std::int32_t, std::int32_t>>& event_slots,
             const ros::Time& stamp, visualization_msgs::MarkerArray* out);

 private:
  // Next marker of the output, every field reset (its vectors and strings keep capacity).
  visualization_msgs::Marker& add(const char* ns, std::int32_t id, const ros::Time& stamp,
                                  std::uint8_t action, visualization_msgs::MarkerArray* out);

  std::string frame_;
  ros::Duration lifetime_;
  std::size_t used_ = 0;              // markers written into the output this build
  std::vector<std::uint8_t> shown_;   // per slot: body namespaces shown last build (bits)
  std::vector<std::uint8_t> showing_; // the same, this build
  PairTable pairs_;                   // shown pairs: user = marker id, stamp = last build
  std::vector<std::int32_t> free_ids_;
  std::int32_t next_id_ = 0;
  std::uint32_t serial_ = 0;          // builds so far
};

}  // namespace workspace_proximity
