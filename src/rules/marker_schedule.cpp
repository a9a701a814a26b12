#include "workspace_proximity/rules/marker_schedule.hpp"

namespace workspace_proximity {

bool MarkerSchedule::due(Stamp now, double marker_rate, double cycle_rate) {
  // Less half a cycle: cycles jitter, and a marker period that is a whole number of cycles
  // must not slip to one more.
  if (last_ != 0 && now >= last_ &&
      secondsBetween(last_, now) < 1.0 / marker_rate - delay(cycle_rate)) {
    return false;
  }
  last_ = now;
  return true;
}

}  // namespace workspace_proximity
