#pragma once
/// The node's parameters as one table: a row per parameter with its name on the parameter
/// server, the member of MonitorParams it sets, its range, unit and whether it can change while
/// the node runs. The ROS reader (ros_params), validate(), the unknown-keys check, the
/// dynamic_reconfigure bridge and Monitor::setParams all walk these rows; test_param_files
/// checks cfg/ProximityMonitor.cfg, config/*.yaml and the docs' parameter tables against them.
///
/// Defaults are the members' initializers (MonitorParams, SsmParams, LabelSettings): a row
/// reads its default from a default-constructed struct, so each default is written once.
///
/// Adding a number the operator can tune while the node runs: the member (with its default),
/// a row here, a slider in cfg/ProximityMonitor.cfg, a line in config/proximity_monitor.yaml
/// and a row in the docs' parameter table; test_param_files fails until the last three agree
/// with the row.

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

/// What a row holds, and so how it is read from the parameter server and checked.
enum class ParamType : std::uint8_t {
  kNumber,      ///< double; an integer on the server is a number too; checked against [min, max]
  kInteger,     ///< int; checked against [min, max]
  kBool,
  kString,
  kStringList,  ///< names: none empty, none listed twice
  kPairs,       ///< [[selector, selector], ...]
  kStructure,   ///< robot_bodies, labels, robot_thresholds: read and checked by their own code
};

/// When a row's value may change.
enum class Tuning : std::uint8_t {
  /// A rule tunable while the node runs: a slider of cfg/ProximityMonitor.cfg
  /// (dynamic_reconfigure). Monitor::setParams takes a new value.
  kLive,
  /// A rule set at start-up (no slider). Monitor::setParams takes a new value all the same.
  kStartup,
  /// Wiring: frames, topics, the robot's bodies, where the outputs go. Fixed once the node is
  /// built; Monitor::setParams keeps the value the monitor was built with (keepWiring()).
  kWiring,
};

/// Where a row's value lives in MonitorParams: the accessor of the row's type (the others
/// null), and a copy of the member whatever its type.
struct ParamMember {
  using Copy = void (*)(const MonitorParams& from, MonitorParams& to);
  ParamType type = ParamType::kStructure;
  double& (*number)(MonitorParams&) = nullptr;
  int& (*integer)(MonitorParams&) = nullptr;
  bool& (*flag)(MonitorParams&) = nullptr;
  std::string& (*text)(MonitorParams&) = nullptr;
  std::vector<std::string>& (*names)(MonitorParams&) = nullptr;
  std::vector<std::pair<std::string, std::string>>& (*pairs)(MonitorParams&) = nullptr;
  Copy copy = nullptr;

  constexpr static ParamMember of(double& (*f)(MonitorParams&), Copy c) {
    ParamMember m;
    m.type = ParamType::kNumber;
    m.number = f;
    m.copy = c;
    return m;
  }
  constexpr static ParamMember of(int& (*f)(MonitorParams&), Copy c) {
    ParamMember m;
    m.type = ParamType::kInteger;
    m.integer = f;
    m.copy = c;
    return m;
  }
  constexpr static ParamMember of(bool& (*f)(MonitorParams&), Copy c) {
    ParamMember m;
    m.type = ParamType::kBool;
    m.flag = f;
    m.copy = c;
    return m;
  }
  constexpr static ParamMember of(std::string& (*f)(MonitorParams&), Copy c) {
    ParamMember m;
    m.type = ParamType::kString;
    m.text = f;
    m.copy = c;
    return m;
  }
  constexpr static ParamMember of(std::vector<std::string>& (*f)(MonitorParams&), Copy c) {
    ParamMember m;
    m.type = ParamType::kStringList;
    m.names = f;
    m.copy = c;
    return m;
  }
  constexpr static ParamMember of(std::vector<std::pair<std::string, std::string>>& (*f)(MonitorParams&),
                                  Copy c) {
    ParamMember m;
    m.type = ParamType::kPairs;
    m.pairs = f;
    m.copy = c;
    return m;
  }
  /// Any other member (robot_bodies, labels, robot_thresholds): copied only, and read and
  /// checked by their own code.
  template <typename T>
  constexpr static ParamMember of(T& (*)(MonitorParams&), Copy c) {
    static_assert(!std::is_arithmetic<T>::value, "a number of the table is a double or an int");
    ParamMember m;
    m.copy = c;
    return m;
  }
};

/// The ParamMember of `path`, a member of MonitorParams (`horizon`, `ssm.hold_time`); its type
/// follows the member's.
#define WP_PARAM_MEMBER(path)                                                          \
  ::workspace_proximity::ParamMember::of(                                              \
      +[](::workspace_proximity::MonitorParams& p) -> auto& { return p.path; },       \
      +[](const ::workspace_proximity::MonitorParams& from,                            \
          ::workspace_proximity::MonitorParams& to) { to.path = from.path; })

/// One parameter of the node's namespace.
struct ParamRow {
  /// On the parameter server under the node's private namespace: "horizon", "ssm/hold_time".
  const char* name;
  ParamMember member;
  Tuning tuning;
  /// Numbers and integers: validate() allows [min, max], both ends included (the slider's
  /// range for a live row). Unused for other types.
  double min;
  double max;
  /// When set, the name of another row whose value validate() uses as the upper end instead
  /// of `max` (stale_after <= track_timeout); `max` stays the slider's end.
  const char* at_most;
  const char* unit;  ///< "s", "m/s", "" (a plain number or no number)
  /// validate()'s words after the unit in its range message ("(at most ~track_timeout)"), or "".
  const char* note;
  const char* doc;   ///< one line
};

/// One setting of a label (labels/<label>/<key>), and of the robot's thresholds
/// (robot_thresholds/<key>) unless `track_only`.
struct LabelRow {
  const char* key;
  double LabelSettings::*member;
  Tuning tuning;
  /// Not a robot threshold: the robot's margin is robot_margin, and its motion comes from tf
  /// (no approach speed, no growth).
  bool track_only;
  double min;  ///< validate() allows [min, max], both ends included
  double max;
  const char* at_most;  ///< a key whose value validate() uses as the upper end instead of max
  const char* unit;
  const char* note;     ///< validate()'s words after the unit, or ""
  const char* doc;
};

/// A table: `size` rows from `rows`.
template <typename Row>
struct ParamRows {
  const Row* rows;
  std::size_t size;
  const Row* begin() const { return rows; }
  const Row* end() const { return rows + size; }
};

/// Every parameter of the node's namespace, in the order the reader reads and validate()
/// checks them. Label settings are in labelTable().
ParamRows<ParamRow> paramTable();
/// The settings of each label (and of robot_thresholds).
ParamRows<LabelRow> labelTable();

/// The row named `name` ("ssm/hold_time"), or null.
const ParamRow* findParam(const std::string& name);
/// The label row of `key` ("margin"), or null.
const LabelRow* findLabelSetting(const std::string& key);

/// A number or integer row's value in `p`, as a double.
double numberOf(const ParamRow& row, const MonitorParams& p);
}  // namespace workspace_proximity
