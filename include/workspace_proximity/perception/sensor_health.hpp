#pragma once
/// Each sensor's health for the perception front end: when it last gave a usable frame, and
/// what is wrong with it now. Unknown is never clear: a sensor never heard, silent for longer
/// than the timeout, whose frame tf cannot place or whose frame came without robot poses is
/// named in a DEGRADED reason for as long as that lasts. A malformed frame does not count as
/// heard (it is counted and named). ROS-free; times are nanoseconds on the caller's clock.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/perception/cloud_frame.hpp"

namespace workspace_proximity {
namespace perception {

class SensorHealth {
 public:
  /// `names`: one per sensor (the topic), `timeout`: s without a usable frame before the
  /// sensor counts as silent; `start`: ns, when listening began.
  SensorHealth(std::vector<std::string> names, double timeout, std::int64_t start);

  int size() const { return static_cast<int>(sensors_.size()); }
  const std::string& name(int s) const { return at(s).name; }

  /// A frame was processed at `now`. `robot_problem`: why the robot could not be posed at
  /// the frame's stamp ("" when it was): the frame counts as heard, but the sensor stays
  /// DEGRADED until a frame comes with the robot posed.
  void frameUsed(int s, std::int64_t now, const CloudFrameStats& stats, const std::string& robot_problem);
  /// A frame was refused as malformed (`reason` names why).
  void frameRejected(int s, std::int64_t now, const std::string& reason);
  /// tf could not place a frame in the fixed frame (`why`).
  void frameUnplaced(int s, std::int64_t now, const std::string& why);

  /// One line per sensor problem at `now`, appended to `out`; none when all are well.
  void degradedReasons(std::int64_t now, std::vector<std::string>* out) const;

  std::int64_t framesUsed(int s) const { return at(s).used; }
  std::int64_t framesRejected(int s) const { return at(s).rejected; }
  std::int64_t framesUnplaced(int s) const { return at(s).unplaced; }
  const std::string& lastRejection(int s) const { return at(s).last_rejection; }
  /// The last processed frame's figures (points per stage, clusters, near-robot count).
  const CloudFrameStats& lastStats(int s) const { return at(s).stats; }

 private:
  struct Sensor {
    std::string name;
    std::int64_t last_used = -1;  // ns; -1: never
    std::int64_t used = 0, rejected = 0, unplaced = 0;
    std::string last_rejection;
    std::string frame_problem;  // the latest frame could not be placed: why
    std::string robot_problem;  // the latest used frame came without robot poses: why
    CloudFrameStats stats;
  };
  const Sensor& at(int s) const { return sensors_[static_cast<std::size_t>(s)]; }
  Sensor& at(int s) { return sensors_[static_cast<std::size_t>(s)]; }

  std::vector<Sensor> sensors_;
  std::int64_t timeout_ns_;
  std::int64_t start_;
};

}  // namespace perception
}  // namespace workspace_proximity
