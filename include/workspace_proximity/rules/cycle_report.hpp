#pragma once
/// What one prediction cycle concluded, built once right after ProximityWorld::predict and
/// read by every output (contacts, markers, diagnostics, the offline replay): the events with
/// their levels and stale flags, each body's worst level, and whether the prediction rests on
/// fresh data (OK) or not (DEGRADED, with one line per reason). No output reads another's.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "workspace_proximity/rules/level_policy.hpp"
#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/pair_event.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

class TrackTable;
class RobotBodies;

/// A body live at the cycle.
struct ReportedBody {
  BodyHandle handle;
  bool robot = false;
};

struct CycleReport {
  Stamp stamp = 0;  ///< the prediction instant (t = 0 of every event)
  /// This cycle's events, earliest first (END events last): the world's own list, valid until
  /// the next predict. Empty before the first cycle.
  const std::vector<PairEvent>* events = nullptr;
  std::vector<Level> levels;        ///< per event
  std::vector<std::uint8_t> stale;  ///< per event: 1 when a body of the pair is predicted from old data
  /// Per world body slot: worst level of its BEGIN / ONGOING events, -1 for none.
  std::vector<std::int8_t> body_level;
  std::vector<ReportedBody> bodies;  ///< live bodies: tracks, then robot bodies present
  bool degraded = false;
  std::vector<std::string> status_lines;  ///< one per reason the status is DEGRADED
  /// Share of the protective volume no sensor saw, from ~perception_status_topics (the
  /// largest); NaN without perception front ends, or while one's is unknown.
  double unseen_share = std::numeric_limits<double>::quiet_NaN();
  WorldStats stats;
  SsmVerdict ssm;  ///< speed and separation monitoring: the speed scale and why

  std::size_t eventCount() const { return events == nullptr ? 0 : events->size(); }
  const PairEvent& event(std::size_t i) const { return (*events)[i]; }
  /// Worst level of body slot `slot` this cycle, -1 for none.
  int bodyLevel(std::int32_t slot) const {
    const auto s = static_cast<std::size_t>(slot);
    return s < body_level.size() ? body_level[s] : -1;
  }
};

/// Everything the report is built from.
struct ReportInputs {
  Stamp now = 0;
  const std::vector<PairEvent>* events = nullptr;
  const ProximityWorld* world = nullptr;
  const TrackTable* tracks = nullptr;
  const RobotBodies* robot = nullptr;
  const LabelTable* labels = nullptr;
  double stale_after = 0.0;  ///< s: a track older than this makes its pairs stale
};

/// Levels, stale flags and body levels from the inputs; `out`'s status fields are left alone
/// (the monitor fills them). Reuses `out`'s storage: allocation-free in steady state.
void buildEventReport(const ReportInputs& in, CycleReport* out);

}  // namespace workspace_proximity
