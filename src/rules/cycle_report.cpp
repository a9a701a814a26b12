#include "workspace_proximity/rules/cycle_report.hpp"

#include <algorithm>

#include "workspace_proximity/rules/robot_bodies.hpp"
#include "workspace_proximity/rules/track_table.hpp"

namespace workspace_proximity {
namespace {

// Settings index of a body: its track's label, or the robot thresholds.
int settingsOf(const ReportInputs& in, std::int32_t slot) {
  const int track = in.tracks->trackOfSlot(slot);
  return track >= 0 ? in.tracks->track(track).settings : LabelTable::kRobot;
}

bool bodyStale(const ReportInputs& in, std::int32_t slot) {
  const int track = in.tracks->trackOfSlot(slot);
  if (track >= 0) return secondsBetween(in.tracks->track(track).stamp, in.now) > in.stale_after;
  const int robot = in.robot->robotOfSlot(slot);
  return robot >= 0 && in.robot->stale(robot);
}

}  // namespace

void buildEventReport(const ReportInputs& in, CycleReport* out) {
  out->stamp = in.now;
  out->events = in.events;
  const std::size_t n = in.events->size();
  out->levels.resize(n);
  out->stale.resize(n);
  out->bodies.clear();
  for (int i = 0; i < in.tracks->size(); ++i) out->bodies.push_back({in.tracks->track(i).handle, false});
  for (int i = 0; i < in.robot->size(); ++i) {
    if (in.robot->present(i)) out->bodies.push_back({in.robot->handle(i), true});
  }
  std::int32_t slots = 0;
  for (const ReportedBody& b : out->bodies) slots = std::max(slots, b.handle.index + 1);
  for (const PairEvent& e : *in.events) slots = std::max({slots, e.body_a.index + 1, e.body_b.index + 1});
  out->body_level.assign(static_cast<std::size_t>(slots), -1);

  for (std::size_t i = 0; i < n; ++i) {
    const PairEvent& e = (*in.events)[i];
    const Level level = contactLevel(e, in.labels->settings(settingsOf(in, e.body_a.index)),
                                     in.labels->settings(settingsOf(in, e.body_b.index)));
    out->levels[i] = level;
    out->stale[i] = 0;
    if (e.state == ContactState::kEnd) continue;
    out->stale[i] = (bodyStale(in, e.body_a.index) || bodyStale(in, e.body_b.index)) ? 1 : 0;
    for (std::int32_t slot : {e.body_a.index, e.body_b.index}) {
      std::int8_t& worst = out->body_level[static_cast<std::size_t>(slot)];
      worst = std::max(worst, static_cast<std::int8_t>(level));
    }
  }
}

}  // namespace workspace_proximity
