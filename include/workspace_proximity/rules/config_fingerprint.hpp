#pragma once
/// The fingerprint of the configuration in force: a hash of every parameter of the table
/// (param_table.hpp), each label's settings, the robot's thresholds and extra bodies, and the
/// URDF text the robot bodies come from. Two runs with the same fingerprint ran the same
/// configuration; the audit trail (audit_log.hpp), safety_status, /diagnostics and the replay's
/// summary carry it.
///
/// The hash is FNV-1a 64 over a canonical text, one `name=value` line per parameter in the
/// table's order:
///   numbers      the shortest %.15g..%.17g that reads back as the same double (exact),
///                integers in decimal, bools true/false;
///   strings      "..." with \\, \", \n, \r, \t and \xHH escaped;
///   lists        ["a","b"], pairs [["a","b"],["c","d"]]: in their order (a list given in
///                another order is another configuration: never a change hidden);
///   labels       labels/<label>/<key>=..., the labels sorted by name (a map: the order they
///                were given in means nothing), every key of labelTable(); in a label's
///                name \, =, / and control characters are written \xHH;
///   thresholds   robot_thresholds/<key>=..., the keys that are not track-only;
///   robot_bodies robot_bodies/<i>=name,frame,shape,dimensions,offset (in their order);
///   URDF         robot_description=<FNV-1a 64 of the text> while ~use_robot_description,
///                else robot_description="" (its meshes are not read).
/// Off the hot path: computed at start-up and on a parameter change.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

/// FNV-1a, 64 bits, of `bytes`.
std::uint64_t fnv1a64(const std::string& bytes);

/// `value` as 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

/// The canonical text of the configuration (see above): `name=value` lines, each ended by '\n'.
/// `urdf`: the URDF text the robot bodies are read from ("" = none). Throws std::logic_error
/// for a structure row of the table this file does not know (a new one must be added here).
std::string canonicalConfig(const MonitorParams& params, const std::string& urdf = std::string());

/// hex64(fnv1a64(canonicalConfig(params, urdf))).
std::string configFingerprint(const MonitorParams& params, const std::string& urdf = std::string());

/// What differs between two configurations, one "name: old -> new" per canonical line that
/// differs (a line only one side has reads "(none)" on the other), in the canonical order.
std::vector<std::string> configChanges(const MonitorParams& before, const MonitorParams& after,
                                       const std::string& urdf = std::string());

}  // namespace workspace_proximity
