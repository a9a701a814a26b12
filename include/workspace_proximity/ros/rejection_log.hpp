#pragma once
/// Logs the monitor's rejections with rosconsole, throttled per reason (each reason at most
/// once per `period` wall seconds, with the number suppressed since), so a flood of one kind
/// never hides another. Superseded arrays are normal with a tracker faster than the node and
/// are only counted, never logged.

#include <array>

#include <ros/time.h>

#include "workspace_proximity/rules/drop.hpp"

namespace workspace_proximity {

class RejectionLog : public RejectionSink {
 public:
  explicit RejectionLog(double period = 2.0) : period_(period) {}
  void onRejection(const Rejection& rejection) override;

 private:
  static constexpr std::size_t kReasons = static_cast<std::size_t>(Drop::kCount);
  double period_;
  std::array<ros::WallTime, kReasons> last_{};
  std::array<std::uint64_t, kReasons> suppressed_{};
};

}  // namespace workspace_proximity
