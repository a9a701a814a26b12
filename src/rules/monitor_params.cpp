#include "workspace_proximity/rules/monitor_params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "workspace_proximity/rules/param_table.hpp"

namespace workspace_proximity {
namespace {

// "~name = value: must be in [lo, hi] unit"
void checkRange(std::vector<std::string>* errors, const std::string& name, double value,
                double lo, double hi, const std::string& unit) {
  if (std::isfinite(value) && value >= lo && value <= hi) return;
  std::ostringstream s;
  s << "~" << name << " = " << value << ": must be in [" << lo << ", " << hi << "] " << unit;
  errors->push_back(s.str());
}

// `unit` and `note` as validate() words them after the range: "s", "(a speed scale)",
// "s (at most ~track_timeout)".
std::string rangeUnit(const char* unit, const char* note) {
  std::string s = unit;
  if (*note != '\0') s += (s.empty() ? "" : " ") + std::string(note);
  return s;
}

// Every label setting of the table in [min, max] (or [min, the at_most setting]); the robot's
// thresholds have only the settings that are not track_only.
void checkLabel(std::vector<std::string>* errors, const std::string& prefix,
                const LabelSettings& l, bool track_label) {
  for (const LabelRow& row : labelTable()) {
    if (row.track_only && !track_label) continue;
    const double hi = row.at_most != nullptr ? l.*findLabelSetting(row.at_most)->member : row.max;
    checkRange(errors, prefix + "/" + row.key, l.*row.member, row.min, hi,
               rangeUnit(row.unit, row.note));
  }
}

void checkNames(std::vector<std::string>* errors, const std::string& name,
                const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) errors->push_back("~" + name + "[" + std::to_string(i) + "]: must not be empty");
    for (std::size_t j = 0; j < i; ++j) {
      if (names[i] == names[j]) errors->push_back("~" + name + ": '" + names[i] + "' is listed twice");
    }
  }
}

// The rows' own rules: numbers in their range, lists of names without empty or repeated ones.
void checkRows(std::vector<std::string>* errors, const MonitorParams& p) {
  MonitorParams& q = const_cast<MonitorParams&>(p);  // the accessors only read here
  for (const ParamRow& row : paramTable()) {
    switch (row.member.type) {
      case ParamType::kNumber:
      case ParamType::kInteger: {
        const double hi = row.at_most != nullptr ? numberOf(*findParam(row.at_most), p) : row.max;
        checkRange(errors, row.name, numberOf(row, p), row.min, hi, rangeUnit(row.unit, row.note));
        break;
      }
      case ParamType::kStringList:
        checkNames(errors, row.name, row.member.names(q));
        break;
      default:
        break;
    }
  }
}

void checkSsmOutputs(std::vector<std::string>* errors, const SsmParams& s) {
  if (s.cmd_vel_in.empty() != s.cmd_vel_out.empty()) {
    errors->push_back("~ssm/cmd_vel_in and ~ssm/cmd_vel_out: give both (the Twist filter) or neither");
  } else if (!s.cmd_vel_in.empty() && s.cmd_vel_in == s.cmd_vel_out) {
    errors->push_back("~ssm/cmd_vel_out = '" + s.cmd_vel_out +
                      "': must differ from ~ssm/cmd_vel_in (the filter would hear itself)");
  }
  if (s.restart != "automatic" && s.restart != "manual") {
    errors->push_back("~ssm/restart = '" + s.restart + "': must be 'automatic' or 'manual'");
  }
  // Category 1 exists to request the halt: without a way to send it, it would only hold.
  if (s.stop_category == 1 && s.halt_service.empty() == s.halt_topic.empty()) {
    errors->push_back("~ssm/stop_category = 1: set exactly one of ~ssm/halt_service and "
                      "~ssm/halt_topic (where the halt goes)");
  }
}

// tf2 refuses frame ids that are empty or start with '/' (a tf1 habit) in every lookup, so
// such a frame would start the node and then fail every cycle: refuse it up front.
void checkFrame(std::vector<std::string>* errors, const std::string& name, const std::string& frame) {
  if (frame.empty()) {
    errors->push_back("~" + name + ": must not be empty");
  } else if (frame[0] == '/') {
    errors->push_back("~" + name + " = '" + frame + "': tf2 frame ids cannot start with '/' (use '" +
                      frame.substr(frame.find_first_not_of('/') == std::string::npos
                                       ? frame.size()
                                       : frame.find_first_not_of('/')) +
                      "')");
  }
}

}  // namespace

MonitorParams::MonitorParams() { labels["default"] = LabelSettings(); }

const LabelSettings& MonitorParams::label(const std::string& name) const {
  auto it = labels.find(name);
  if (it != labels.end()) return it->second;
  return labels.at("default");
}

std::vector<std::string> validate(const MonitorParams& p) {
  std::vector<std::string> errors;
  checkFrame(&errors, "fixed_frame", p.fixed_frame);
  checkRows(&errors, p);
  if (p.marker_rate > 0.0 && p.rate > 0.0 &&
      p.marker_lifetime <= 1.0 / std::min(p.marker_rate, p.rate)) {
    errors.push_back("~marker_lifetime: must be longer than the marker period 1 / min(~marker_rate, "
                     "~rate) (markers would blink)");
  }
  // The hand-off sleeps in every cycle: at most a quarter of the period (the default's 0.2 ms
  // passes at the highest rate, 1 000 Hz).
  if (p.rate > 0.0 && p.safety_handoff > 0.25 / p.rate) {
    errors.push_back("~safety_handoff: must be at most a quarter of the cycle period 0.25 / ~rate "
                     "(the cycle sleeps this long every period)");
  }
  if (p.cycle_trigger != "timer" && p.cycle_trigger != "input") {
    errors.push_back("~cycle_trigger = '" + p.cycle_trigger + "': must be 'timer' or 'input'");
  }
  if (!p.trigger_source.empty()) {
    const std::vector<std::string> topics =
        p.input_topics.empty() ? std::vector<std::string>{"tracked_objects"} : p.input_topics;
    if (std::find(topics.begin(), topics.end(), p.trigger_source) == topics.end()) {
      errors.push_back("~trigger_source = '" + p.trigger_source +
                       "': must be one of the input topics (as ~input_topics lists them, or "
                       "'tracked_objects' without ~input_topics)");
    }
  }
  for (const std::string& topic : p.skeleton_marker_topics) {
    const std::vector<std::string> topics =
        p.input_topics.empty() ? std::vector<std::string>{"tracked_objects"} : p.input_topics;
    if (std::find(topics.begin(), topics.end(), topic) == topics.end()) {
      errors.push_back("~skeleton_marker_topics: '" + topic +
                       "' must be one of the input topics (as ~input_topics lists them)");
    }
  }
  checkSsmOutputs(&errors, p.ssm);
  if (p.labels.count("default") == 0) errors.push_back("~labels: must have a 'default' entry");
  for (const auto& kv : p.labels) checkLabel(&errors, "labels/" + kv.first, kv.second, true);
  checkLabel(&errors, "robot_thresholds", p.robot_thresholds, false);

  for (std::size_t i = 0; i < p.robot_bodies.size(); ++i) {
    const RobotBodySpec& b = p.robot_bodies[i];
    const std::string where = "~robot_bodies[" + std::to_string(i) + "]";
    if (b.name.empty()) errors.push_back(where + "/name: must not be empty");
    checkFrame(&errors, where.substr(1) + "/frame", b.frame);
    if (!b.shape.valid()) errors.push_back(where + "/size: every edge must be finite and > 0 m");
    if (!b.offset.matrix().allFinite() ||
        b.offset.translation().cwiseAbs().maxCoeff() > Limits::kMaxCoordinate) {
      errors.push_back(where + "/offset: xyz must be finite and within 1e7 m");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (p.robot_bodies[j].name == b.name) {
        errors.push_back(where + "/name: '" + b.name + "' is used twice");
      }
    }
  }
  try {
    makePairRules(p);
  } catch (const std::invalid_argument& e) {
    errors.push_back(std::string("~ignore_pairs / ~check_pairs: ") + e.what());
  }
  return errors;
}

PairRules makePairRules(const MonitorParams& p) {
  PairRules rules;  // default: robot-robot skipped
  for (const auto& pair : p.ignore_pairs) rules.add(pair.first, pair.second, false);
  for (const auto& pair : p.check_pairs) rules.add(pair.first, pair.second, true);
  return rules;
}

}  // namespace workspace_proximity
