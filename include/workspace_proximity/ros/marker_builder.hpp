#pragma once
/// RViz markers for the bodies, their swept volumes, predicted contacts and velocities,
/// rendered from a cycle's report.

#include <cstdint>
#include <string>
#include <vector>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "workspace_proximity/rules/cycle_report.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

/// Builds one MarkerArray from a report. Namespaces: "bodies", "swept", "velocity", "ids" (one
/// marker per body, id = its world slot, stable for the body's life; "ids" is the body's id as
/// a small label), "nearest" and "ttc_text" (one per predicted pair, id = the pair's id, stable
/// for the pair's life; the text names the pair: "person_3 - tool 0.42 s"), "status" (one line
/// above the scene: OK or DEGRADED with the first reason, the earliest contact, and the speed
/// scale), "ssm" (speed and separation monitoring's limiting pair: its robot body grown by the
/// protective separation S_p as a translucent box in the scale's colour, id 0; the line between
/// the pair's nearest points, id 1; "scale 0.42: person_1 0.83 m < S_p 1.11 m", id 2). Markers shown by the
/// last build but not by this one are sent with action DELETE; every marker has `lifetime`,
/// so everything vanishes if the node stops. Bookkeeping is in flat arrays indexed by slot
/// and pair id; the output array is rewritten in place, so steady builds allocate (almost)
/// nothing.
class MarkerBuilder {
 public:
  MarkerBuilder(const std::string& frame, double lifetime);
  /// s, from the next build on.
  void setLifetime(double lifetime) { lifetime_ = ros::Duration(lifetime); }

  /// Markers of `report` (bodies named and posed from `world`), stamped with the report's
  /// instant.
  void build(const CycleReport& report, const ProximityWorld& world,
             visualization_msgs::MarkerArray* out);

 private:
  // Next marker of the output, every field reset (its vectors and strings keep capacity).
  visualization_msgs::Marker& add(const char* ns, std::int32_t id, std::uint8_t action,
                                  visualization_msgs::MarkerArray* out);
  // `muted`: a track muted this cycle (~mute), shown by its id text.
  void addBody(const ReportedBody& body, int level, bool muted, const ProximityWorld& world,
               visualization_msgs::MarkerArray* out);
  void addPair(const PairEvent& event, Level level, const ProximityWorld& world,
               visualization_msgs::MarkerArray* out);
  void addStatus(const CycleReport& report, const ProximityWorld& world,
                 visualization_msgs::MarkerArray* out);
  void addSsm(const CycleReport& report, const ProximityWorld& world,
              visualization_msgs::MarkerArray* out);
  void deleteVanished(visualization_msgs::MarkerArray* out);

  std::string frame_;
  ros::Duration lifetime_;
  ros::Time stamp_;                   // of the build under way
  std::size_t used_ = 0;              // markers written into the output this build
  std::vector<std::uint8_t> shown_;   // per body slot: namespaces shown last build (bits)
  std::vector<std::uint8_t> showing_; // the same, this build
  std::vector<std::uint8_t> pair_shown_;    // per pair id: shown last build
  std::vector<std::uint8_t> pair_showing_;  // the same, this build
  std::string status_text_;                 // reused
  bool ssm_shown_ = false;                  // the "ssm" markers were shown last build
};

}  // namespace workspace_proximity
