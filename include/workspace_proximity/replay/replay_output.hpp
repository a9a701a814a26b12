#pragma once
/// What a replay leaves behind, in one folder:
///   events.csv    one row per event of every cycle: stamp, t, state, id_a, id_b, label_a,
///                 label_b, time_to_contact, time_to_separation, distance, closing_speed,
///                 level, stale (the ContactEvent fields the node publishes; END rows have
///                 time_to_contact inf);
///   cycles.csv    one row per cycle: stamp, t, status, events, tracks, robot_bodies,
///                 robot_unposed, details (the DEGRADED lines, joined by " | "), and speed and
///                 separation monitoring's speed_scale, raw_scale and limiting pair (ssm_robot,
///                 ssm_object, separation, required_separation, approach_speed; empty when
///                 nothing is within reach, all seven empty with ~ssm/enabled false);
///   summary.json  the whole replay: bag, configuration (and its config_fingerprint, as the
///                 node would publish it), counts, drops by reason, speed.
/// `stamp` is the cycle's instant (bag time, s since the epoch, to the nanosecond) and `t` the
/// same in seconds since the bag's first message. Columns are named in the first row and
/// readers (tools/replay_report.py) address them by name: a column added later goes at the end
/// of a row and breaks nothing.
/// Rows are written as the cycles come (memory does not grow with the bag's length).

#include <cstdio>
#include <string>
#include <vector>

#include "workspace_proximity/replay/bag_replay.hpp"

namespace workspace_proximity {

/// The replay's inputs, for the summary.
struct ReplayInfo {
  std::string bag;
  std::vector<std::string> config_files;
  std::string urdf;
  std::vector<std::string> warnings;   ///< URDF elements skipped, duplicate names
  const BagInput* input = nullptr;     ///< topics of the bag
  const ReplaySetup* setup = nullptr;  ///< parameters, robot bodies, topics
};

class ReplayWriter : public ReplaySink {
 public:
  /// Creates `out_dir` (and parents) and opens the CSV files. Throws ReplayError (kOutput).
  ReplayWriter(const std::string& out_dir, Stamp bag_begin);
  ~ReplayWriter() override;
  ReplayWriter(const ReplayWriter&) = delete;
  ReplayWriter& operator=(const ReplayWriter&) = delete;

  void onCycle(const CycleReport& report, const ContactEventArray& contacts,
               const Monitor& monitor) override;
  /// Writes summary.json and closes the files. Throws ReplayError (kOutput) when a write failed.
  void finish(const ReplayStats& stats, const ReplayInfo& info);

  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  Stamp begin_;
  std::FILE* events_ = nullptr;
  std::FILE* cycles_ = nullptr;
  std::string line_;     // reused row
  std::string stamp_t_;  // reused: a cycle's stamp and t columns
  std::string details_;  // reused: a cycle's DEGRADED lines
};

/// The short text summary of a replay (printed on stdout by replay_bag).
std::string summaryText(const ReplayStats& stats, const ReplayInfo& info);

/// `stats` as JSON (summary.json).
std::string summaryJson(const ReplayStats& stats, const ReplayInfo& info);

}  // namespace workspace_proximity
