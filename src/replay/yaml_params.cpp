#include "workspace_proximity/replay/yaml_params.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace workspace_proximity {
namespace {

using XmlRpc::XmlRpcValue;

// PyYAML's implicit resolvers (yaml/resolver.py, YAML 1.1), which decide the type roslaunch
// gives a plain scalar. Matched in PyYAML's order: bool, float, int, null; else a string.
const std::regex& boolPattern() {
  static const std::regex r("yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF");
  return r;
}
const std::regex& floatPattern() {
  static const std::regex r(
      "[-+]?(?:[0-9][0-9_]*)\\.[0-9_]*(?:[eE][-+][0-9]+)?"
      "|\\.[0-9_]+(?:[eE][-+][0-9]+)?"
      "|[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\\.[0-9_]*"
      "|[-+]?\\.(?:inf|Inf|INF)"
      "|\\.(?:nan|NaN|NAN)");
  return r;
}
const std::regex& intPattern() {
  static const std::regex r(
      "[-+]?0b[0-1_]+"
      "|[-+]?0[0-7_]+"
      "|[-+]?(?:0|[1-9][0-9_]*)"
      "|[-+]?0x[0-9a-fA-F_]+"
      "|[-+]?[1-9][0-9_]*(?::[0-5]?[0-9])+");
  return r;
}
const std::regex& nullPattern() {
  static const std::regex r("~|null|Null|NULL|");
  return r;
}

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("~" + name + ": " + what);
}

std::string withoutUnderscores(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c != '_') out.push_back(c);
  }
  return out;
}

// Sign and the rest of a numeral.
int takeSign(std::string* s) {
  if (!s->empty() && ((*s)[0] == '-' || (*s)[0] == '+')) {
    const int sign = (*s)[0] == '-' ? -1 : 1;
    s->erase(0, 1);
    return sign;
  }
  return 1;
}

// "1:30:05" (base 60, as PyYAML reads it) -> 5405.
double sexagesimal(const std::string& digits) {
  double value = 0.0;
  std::stringstream parts(digits);
  std::string part;
  while (std::getline(parts, part, ':')) value = value * 60.0 + std::strtod(part.c_str(), nullptr);
  return value;
}

XmlRpcValue intValue(const std::string& text, const std::string& name) {
  std::string s = withoutUnderscores(text);
  const int sign = takeSign(&s);
  long long magnitude = 0;
  if (s.find(':') != std::string::npos) {
    magnitude = static_cast<long long>(sexagesimal(s));
  } else {
    int base = 10;
    std::size_t skip = 0;
    if (s.size() > 1 && s[0] == '0' && s[1] == 'b') { base = 2; skip = 2; }
    else if (s.size() > 1 && s[0] == '0' && s[1] == 'x') { base = 16; skip = 2; }
    else if (s.size() > 1 && s[0] == '0') { base = 8; skip = 1; }
    errno = 0;
    magnitude = std::strtoll(s.c_str() + skip, nullptr, base);
    if (errno == ERANGE) fail(name, "integer " + text + " is out of range");
  }
  const long long value = sign * magnitude;
  // The parameter server's integers are 32 bits (XML-RPC i4); roslaunch fails on larger ones.
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    fail(name, "integer " + text + " does not fit in 32 bits");
  }
  return XmlRpcValue(static_cast<int>(value));
}

XmlRpcValue floatValue(const std::string& text) {
  std::string s = withoutUnderscores(text);
  const int sign = takeSign(&s);
  if (s == ".inf" || s == ".Inf" || s == ".INF") return XmlRpcValue(sign * std::numeric_limits<double>::infinity());
  if (s == ".nan" || s == ".NaN" || s == ".NAN") return XmlRpcValue(std::numeric_limits<double>::quiet_NaN());
  if (s.find(':') != std::string::npos) return XmlRpcValue(sign * sexagesimal(s));
  return XmlRpcValue(sign * std::strtod(s.c_str(), nullptr));
}

// "file line N" of `node`, or of `context` (its key, or its list) when the node has no mark
// of its own (an empty value has none).
std::string where(const YAML::Node& node, const std::string& file,
                  const YAML::Mark& context = YAML::Mark::null_mark()) {
  YAML::Mark mark = node.Mark();
  if (mark.is_null()) mark = context;
  if (mark.is_null()) return file;
  return file + " line " + std::to_string(mark.line + 1);
}

XmlRpcValue scalar(const YAML::Node& node, const std::string& name, const std::string& file) {
  const std::string& text = node.Scalar();
  const std::string& tag = node.Tag();
  if (tag == "!" || tag == "tag:yaml.org,2002:str") return XmlRpcValue(text);  // quoted, !!str
  if (tag == "tag:yaml.org,2002:float") return floatValue(text);
  if (tag == "tag:yaml.org,2002:int") return intValue(text, name);
  if (tag == "tag:yaml.org,2002:bool") {
    if (!std::regex_match(text, boolPattern())) fail(name, "'" + text + "' is not a boolean");
    return XmlRpcValue(text[0] == 'y' || text[0] == 'Y' || text[0] == 't' || text[0] == 'T' ||
                       text == "on" || text == "On" || text == "ON");
  }
  if (tag != "?") fail(name, "unsupported tag " + tag + " (" + where(node, file) + ")");
  if (std::regex_match(text, boolPattern())) {
    return XmlRpcValue(text[0] == 'y' || text[0] == 'Y' || text[0] == 't' || text[0] == 'T' ||
                       text == "on" || text == "On" || text == "ON");
  }
  if (std::regex_match(text, floatPattern())) return floatValue(text);
  if (std::regex_match(text, intPattern())) return intValue(text, name);
  if (std::regex_match(text, nullPattern())) {
    fail(name, "has no value (" + where(node, file) + ")");
  }
  return XmlRpcValue(text);
}

XmlRpcValue convert(const YAML::Node& node, const std::string& name, const std::string& file,
                    const YAML::Mark& context) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return scalar(node, name, file);
    case YAML::NodeType::Sequence: {
      XmlRpcValue array;
      array.setSize(static_cast<int>(node.size()));
      for (std::size_t i = 0; i < node.size(); ++i) {
        array[static_cast<int>(i)] =
            convert(node[i], name + "[" + std::to_string(i) + "]", file, node.Mark());
      }
      return array;
    }
    case YAML::NodeType::Map: {
      XmlRpcValue dict;
      dict.begin();  // an empty dictionary, also when the map is empty
      for (const auto& kv : node) {
        if (!kv.first.IsScalar()) fail(name, "keys must be names (" + where(kv.first, file) + ")");
        const std::string key = kv.first.Scalar();
        dict[key] = convert(kv.second, name.empty() ? key : name + "/" + key, file, kv.first.Mark());
      }
      return dict;
    }
    case YAML::NodeType::Null:
      // An empty value's own mark is where the next token starts: name its key's line.
      fail(name, "has no value (" + where(context.is_null() ? node : YAML::Node(), file, context) + ")");
    case YAML::NodeType::Undefined:
      break;
  }
  fail(name, "undefined value (" + where(node, file, context) + ")");
}

}  // namespace

XmlRpcValue yamlToParams(const std::string& yaml_text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    std::ostringstream s;
    s << file;
    if (!e.mark.is_null()) s << ":" << e.mark.line + 1 << ":" << e.mark.column + 1;
    s << ": YAML syntax error: " << e.msg;
    throw std::runtime_error(s.str());
  }
  if (root.IsNull()) {  // an empty file sets nothing
    XmlRpcValue empty;
    empty.begin();
    return empty;
  }
  if (!root.IsMap()) {
    throw std::runtime_error(file + ": must be a dictionary of parameters (name: value)");
  }
  return convert(root, "", file, root.Mark());
}

XmlRpcValue loadYamlParams(const std::vector<std::string>& files) {
  XmlRpcValue merged;
  merged.begin();
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error(file + ": cannot read the configuration file");
    std::stringstream text;
    text << in.rdbuf();
    mergeParams(&merged, yamlToParams(text.str(), file));
  }
  return merged;
}

void mergeParams(XmlRpcValue* base, const XmlRpcValue& overlay) {
  if (base->getType() != XmlRpcValue::TypeStruct || overlay.getType() != XmlRpcValue::TypeStruct) {
    *base = overlay;
    return;
  }
  for (auto it = overlay.begin(); it != overlay.end(); ++it) {
    if (base->hasMember(it->first)) {
      mergeParams(&(*base)[it->first], it->second);
    } else {
      (*base)[it->first] = it->second;
    }
  }
}

}  // namespace workspace_proximity
