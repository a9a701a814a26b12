#pragma once
/// The node's YAML configuration files as the parameter tree roslaunch would build from them,
/// without a parameter server: the offline replay reads the same files as the node and feeds
/// them to readParams(const XmlRpcValue&), so the same values pass or fail the same checks.
///
/// Plain scalars are typed as roslaunch types them (PyYAML, YAML 1.1): `30` is an integer,
/// `30.0`, `1.0e-3` and `.5` are numbers, `1e-3` and `inf` are strings, `yes` / `off` are
/// booleans. Several files are merged in order the way `<rosparam command="load">` merges
/// them: dictionaries key by key (recursively), every other value replaced by the later one.

#include <string>
#include <vector>

#include <XmlRpcValue.h>

namespace workspace_proximity {

/// One YAML document (a dictionary at the top) as a parameter tree. `where` names the text in
/// messages (a file name). Throws std::runtime_error with `where`, line and column on a YAML
/// syntax error, and naming the parameter ("~labels/person/margin: ...") for a value the
/// parameter server cannot hold (null, an integer beyond 32 bits, an unsupported tag).
XmlRpc::XmlRpcValue yamlToParams(const std::string& yaml_text, const std::string& where);

/// The files read and merged in order (later files win). Throws std::runtime_error naming the
/// file when one cannot be read, and as yamlToParams.
XmlRpc::XmlRpcValue loadYamlParams(const std::vector<std::string>& files);

/// `overlay` merged into `base`: dictionaries key by key, recursively; anything else replaced.
void mergeParams(XmlRpc::XmlRpcValue* base, const XmlRpc::XmlRpcValue& overlay);

}  // namespace workspace_proximity
