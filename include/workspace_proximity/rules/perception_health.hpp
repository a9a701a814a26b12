#pragma once
/// The perception front ends' health as the monitor sees it (issue 23), ROS-free: one entry
/// per `~perception_status_topics` topic (cloud_tracker's PerceptionStatus), turned into the
/// monitor's DEGRADED lines and the unseen share it reports.
///
/// A front end that says it is degraded (a sensor silent, not placed by tf, without robot
/// poses, the unseen share above its limit: its reasons name the sensor) makes the monitor's
/// status DEGRADED with each reason, prefixed by the topic; a status topic never heard, or
/// silent for longer than the timeout, is DEGRADED too (unknown is never clear).
/// The unseen share reported is the largest of the fresh statuses' (NaN: no front end, none
/// heard, or one without a share).

#include <cstddef>
#include <string>
#include <vector>

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

class PerceptionHealth {
 public:
  /// `topics`: resolved status topic names, in ~perception_status_topics' order.
  explicit PerceptionHealth(std::vector<std::string> topics = {});

  /// A status of topic `i` received at `now`. `reasons` are copied (a handful of lines).
  void onStatus(int i, Stamp now, bool degraded, const std::vector<std::string>& reasons,
                double unseen_share);
  /// Appends one line per problem at `now` with statuses older than `timeout` s silent.
  void statusLines(Stamp now, double timeout, std::vector<std::string>* lines) const;
  /// The largest unseen share of the statuses heard within `timeout` s of `now`; NaN when
  /// there is none, or when one of them has none (unknown).
  double unseenShare(Stamp now, double timeout) const;
  /// Forgets every receipt (the clock went back).
  void reset();

  std::size_t size() const { return topics_.size(); }
  const std::string& topic(int i) const { return topics_[static_cast<std::size_t>(i)]; }

 private:
  struct Entry {
    Stamp received = 0;  // 0: never heard
    bool degraded = false;
    std::vector<std::string> reasons;
    double unseen_share = 0.0;
  };
  std::vector<std::string> topics_;
  std::vector<Entry> entries_;
};

}  // namespace workspace_proximity
