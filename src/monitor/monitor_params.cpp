#include "workspace_proximity/monitor/monitor_params.hpp"

#include <algorithm>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace workspace_proximity {
namespace {

// "~name = value: must be in [lo, hi] unit"
void checkRange(std::vector<std::string>* errors, const std::string& name, double value,
                double lo, double hi, const char* unit) {
  if (std::isfinite(value) && value >= lo && value <= hi) return;
  std::ostringstream s;
  s << "~" << name << " = " << value << ": must be in [" << lo << ", " << hi << "] " << unit;
  errors->push_back(s.str());
}

void checkLabel(std::vector<std::string>* errors, const std::string& prefix,
                const LabelSettings& l, bool track_label) {
  if (track_label) checkRange(errors, prefix + "/margin", l.margin, 0.0, 10.0, "m");
  checkRange(errors, prefix + "/warning_time", l.warning_time, 0.0, 60.0, "s");
  checkRange(errors, prefix + "/critical_time", l.critical_time, 0.0, l.warning_time, "s");
  checkRange(errors, prefix + "/warning_distance", l.warning_distance, 0.0, 100.0, "m");
  checkRange(errors, prefix + "/critical_distance", l.critical_distance, 0.0, l.warning_distance,
             "m");
  // The approach speed and the growth of a track's margin (robot_thresholds never have them:
  // readParams refuses the keys there). Ranges are dynamic_reconfigure's sliders and stay
  // inside the core's Limits.
  if (!track_label) return;
  checkRange(errors, prefix + "/ssm_min_speed", l.ssm_min_speed, 0.0, 20.0, "m/s");
  checkRange(errors, prefix + "/position_error", l.position_error, 0.0, 10.0, "m");
  checkRange(errors, prefix + "/velocity_error", l.velocity_error, 0.0, 100.0, "m/s");
  checkRange(errors, prefix + "/max_accel", l.max_accel, 0.0, 1000.0, "m/s^2");
  checkRange(errors, prefix + "/max_speed", l.max_speed, 0.0, 100.0, "m/s (0: no speed cap)");
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

void checkSsm(std::vector<std::string>* errors, const SsmParams& s) {
  checkRange(errors, "ssm/reaction_time", s.reaction_time, 0.0, 10.0, "s");
  checkRange(errors, "ssm/stopping_time", s.stopping_time, 0.0, 10.0, "s");
  checkRange(errors, "ssm/intrusion_distance", s.intrusion_distance, 0.0, 10.0, "m");
  checkRange(errors, "ssm/sensor_uncertainty", s.sensor_uncertainty, 0.0, 10.0, "m");
  checkRange(errors, "ssm/robot_uncertainty", s.robot_uncertainty, 0.0, 10.0, "m");
  checkRange(errors, "ssm/robot_max_speed", s.robot_max_speed, 0.001, 100.0, "m/s");
  checkRange(errors, "ssm/max_increase_rate", s.max_increase_rate, 0.001, 1000.0, "1/s");
  checkRange(errors, "ssm/hold_time", s.hold_time, 0.0, 3600.0, "s");
  checkRange(errors, "ssm/degraded_scale", s.degraded_scale, 0.0, 1.0, "(a speed scale)");
  checkNames(errors, "ssm/labels", s.labels);
  checkNames(errors, "ssm/stop_trajectory_topics", s.stop_trajectory_topics);
  checkNames(errors, "ssm/stop_event_topics", s.stop_event_topics);
  if (s.cmd_vel_in.empty() != s.cmd_vel_out.empty()) {
    errors->push_back("~ssm/cmd_vel_in and ~ssm/cmd_vel_out: give both (the Twist filter) or neither");
  } else if (!s.cmd_vel_in.empty() && s.cmd_vel_in == s.cmd_vel_out) {
    errors->push_back("~ssm/cmd_vel_out = '" + s.cmd_vel_out +
                      "': must differ from ~ssm/cmd_vel_in (the filter would hear itself)");
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
  checkRange(&errors, "rate", p.rate, 0.1, 1000.0, "Hz");
  checkRange(&errors, "horizon", p.horizon, 0.0, 60.0, "s");
  checkRange(&errors, "track_timeout", p.track_timeout, 0.001, 3600.0, "s");
  checkRange(&errors, "stale_after", p.stale_after, 0.0, p.track_timeout, "s (at most ~track_timeout)");
  checkRange(&errors, "source_timeout", p.source_timeout, 0.001, 3600.0, "s");
  checkRange(&errors, "max_future", p.max_future, 0.0, 60.0, "s");
  checkRange(&errors, "max_tracks", p.max_tracks, 1, 1000000, "tracks");
  checkRange(&errors, "robot_margin", p.robot_margin, 0.0, 10.0, "m");
  checkRange(&errors, "velocity_window", p.velocity_window, 0.005, 2.0, "s");
  checkRange(&errors, "tf_timeout", p.tf_timeout, 0.001, 3600.0, "s");
  checkRange(&errors, "trajectory_tolerance", p.trajectory_tolerance, 0.0, 100.0, "rad or m");
  checkRange(&errors, "joint_path_tolerance", p.joint_path_tolerance, 0.0001, 1.0, "m");
  checkRange(&errors, "marker_lifetime", p.marker_lifetime, 0.01, 3600.0, "s");
  checkRange(&errors, "marker_rate", p.marker_rate, 0.1, 1000.0, "Hz");
  if (p.marker_rate > 0.0 && p.rate > 0.0 &&
      p.marker_lifetime <= 1.0 / std::min(p.marker_rate, p.rate)) {
    errors.push_back("~marker_lifetime: must be longer than the marker period 1 / min(~marker_rate, "
                     "~rate) (markers would blink)");
  }
  for (std::size_t i = 0; i < p.input_topics.size(); ++i) {
    if (p.input_topics[i].empty()) {
      errors.push_back("~input_topics[" + std::to_string(i) + "]: must not be empty");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (p.input_topics[i] == p.input_topics[j]) {
        errors.push_back("~input_topics: '" + p.input_topics[i] + "' is listed twice");
      }
    }
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
  checkSsm(&errors, p.ssm);
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
