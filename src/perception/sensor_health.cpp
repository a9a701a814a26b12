#include "workspace_proximity/perception/sensor_health.hpp"

#include <cmath>
#include <cstdio>

namespace workspace_proximity {
namespace perception {

namespace {

std::string seconds(std::int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f s", static_cast<double>(ns) * 1e-9);
  return buf;
}

}  // namespace

SensorHealth::SensorHealth(std::vector<std::string> names, double timeout, std::int64_t start)
    : timeout_ns_(static_cast<std::int64_t>(std::llround(timeout * 1e9))), start_(start) {
  for (std::string& n : names) {
    Sensor s;
    s.name = std::move(n);
    sensors_.push_back(std::move(s));
  }
}

void SensorHealth::frameUsed(int s, std::int64_t now, const CloudFrameStats& stats,
                             const std::string& robot_problem) {
  Sensor& x = at(s);
  x.last_used = now;
  ++x.used;
  x.frame_problem.clear();
  x.robot_problem = robot_problem;
  x.stats = stats;
}

void SensorHealth::frameRejected(int s, std::int64_t now, const std::string& reason) {
  Sensor& x = at(s);
  ++x.rejected;
  x.last_rejection = reason;
}

void SensorHealth::frameUnplaced(int s, std::int64_t now, const std::string& why) {
  Sensor& x = at(s);
  ++x.unplaced;
  x.frame_problem = why;
}

void SensorHealth::degradedReasons(std::int64_t now, std::vector<std::string>* out) const {
  for (const Sensor& x : sensors_) {
    const std::string rejected =
        x.rejected > 0 ? " (" + std::to_string(x.rejected) + " frames rejected, the last as " +
                             x.last_rejection + ")"
                       : "";
    if (x.last_used < 0) {
      // Heard nothing usable yet: named at once, since unknown is never clear.
      out->push_back("sensor " + x.name + ": no usable frame for " + seconds(now - start_) + rejected);
    } else if (now - x.last_used > timeout_ns_) {
      out->push_back("sensor " + x.name + ": silent for " + seconds(now - x.last_used) +
                     " (source_timeout " + seconds(timeout_ns_) + ")" + rejected);
    }
    if (!x.frame_problem.empty()) out->push_back("sensor " + x.name + ": " + x.frame_problem);
    if (x.last_used >= 0 && !x.robot_problem.empty()) {
      out->push_back("sensor " + x.name + ": robot poses unknown at the frame's stamp: " + x.robot_problem);
    }
  }
}

}  // namespace perception
}  // namespace workspace_proximity
