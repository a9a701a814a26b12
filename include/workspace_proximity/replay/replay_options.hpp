#pragma once
/// The command line of replay_bag (and scripts/replay, which passes it on).

#include <string>
#include <vector>

namespace workspace_proximity {

struct ReplayOptions {
  std::string bag;
  std::vector<std::string> config_files;  ///< merged in order, later files win
  std::string urdf;                       ///< robot description file; empty: none
  std::string out_dir;                    ///< default: ./replay-<bag name>
  std::string input_topic;                ///< replaces the default "tracked_objects"
  double rate_factor = 0.0;               ///< 0: as fast as possible
  bool report = true;                     ///< run tools/replay_report.py afterwards
  bool help = false;
};

/// The usage text.
const char* replayUsage();

/// Parses argv[1..]. Returns false with `*error` set on a bad command line.
bool parseReplayOptions(const std::vector<std::string>& args, ReplayOptions* out,
                        std::string* error);

/// A topic name as the node resolves it in the root namespace under the name
/// "proximity_monitor": "tracked_objects" -> "/tracked_objects", "~x" ->
/// "/proximity_monitor/x", absolute names unchanged.
std::string resolveTopic(const std::string& name);

}  // namespace workspace_proximity
