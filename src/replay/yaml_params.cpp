#include "workspace_proximity/replay/yaml_params.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace workspace_proximity {
namespace {

using XmlRpc::XmlRpcValue;

// PyYAML's implicit resolvers (yaml/resolver.py, YAML 1.1), which decide the type roslaunch
// gives a plain scalar, written out as small matchers (std::regex would do, but GCC 12's
// <regex> trips -Wmaybe-uninitialized in the sanitizer build). In PyYAML's order: bool, float,
// int, null; anything else is a string.
//   bool   yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF
//   float  [-+]?[0-9][0-9_]*\.[0-9_]*([eE][-+][0-9]+)?  |  \.[0-9_]+([eE][-+][0-9]+)?
//          | [-+]?[0-9][0-9_]*(:[0-5]?[0-9])+\.[0-9_]*  |  [-+]?\.(inf|Inf|INF)  |  \.(nan|NaN|NAN)
//   int    [-+]?0b[0-1_]+  |  [-+]?0[0-7_]+  |  [-+]?(0|[1-9][0-9_]*)  |  [-+]?0x[0-9a-fA-F_]+
//          | [-+]?[1-9][0-9_]*(:[0-5]?[0-9])+
//   null   ~|null|Null|NULL|(empty)
bool oneOf(const std::string& s, std::initializer_list<const char*> words) {
  for (const char* w : words) {
    if (s == w) return true;
  }
  return false;
}

bool isBool(const std::string& s) {
  return oneOf(s, {"yes", "Yes", "YES", "no", "No", "NO", "true", "True", "TRUE", "false",
                   "False", "FALSE", "on", "On", "ON", "off", "Off", "OFF"});
}

bool boolValue(const std::string& s) {
  return oneOf(s, {"yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"});
}

bool isNull(const std::string& s) { return oneOf(s, {"~", "null", "Null", "NULL", ""}); }

bool isDigit(char c) { return c >= '0' && c <= '9'; }

// Characters from `i` on that satisfy `ok`; returns the index after them.
template <typename Ok>
std::size_t skip(const std::string& s, std::size_t i, Ok ok) {
  while (i < s.size() && ok(s[i])) ++i;
  return i;
}

std::size_t skipSign(const std::string& s) {
  return !s.empty() && (s[0] == '-' || s[0] == '+') ? 1 : 0;
}

// One or more ":" [0-5]?[0-9] groups from `i`; returns the index after them (`i` when none).
std::size_t skipSexagesimal(const std::string& s, std::size_t i) {
  std::size_t at = i;
  while (at < s.size() && s[at] == ':') {
    const std::size_t digits_end = skip(s, at + 1, isDigit);
    const std::size_t n = digits_end - (at + 1);
    if (n == 1 || (n == 2 && s[at + 1] <= '5')) {
      at = digits_end;
    } else {
      return i;
    }
  }
  return at;
}

// An optional exponent [eE][-+][0-9]+ at `i`; returns the index after it, or npos when one is
// started but malformed.
std::size_t skipExponent(const std::string& s, std::size_t i) {
  if (i == s.size() || (s[i] != 'e' && s[i] != 'E')) return i;
  if (i + 1 == s.size() || (s[i + 1] != '-' && s[i + 1] != '+')) return std::string::npos;
  const std::size_t end = skip(s, i + 2, isDigit);
  return end == i + 2 ? std::string::npos : end;
}

bool isFloat(const std::string& s) {
  if (oneOf(s, {".nan", ".NaN", ".NAN"})) return true;
  const std::size_t sign = skipSign(s);
  const std::string rest = s.substr(sign);
  if (oneOf(rest, {".inf", ".Inf", ".INF"})) return true;
  auto digitOrUnderscore = [](char c) { return isDigit(c) || c == '_'; };
  if (sign == 0 && !s.empty() && s[0] == '.') {  // .[0-9_]+ exponent?
    const std::size_t end = skip(s, 1, digitOrUnderscore);
    return end > 1 && skipExponent(s, end) == s.size();
  }
  if (sign == s.size() || !isDigit(s[sign])) return false;
  std::size_t at = skip(s, sign + 1, digitOrUnderscore);
  const std::size_t after_groups = skipSexagesimal(s, at);
  if (after_groups != at) {  // base 60: a fraction but no exponent
    if (after_groups == s.size() || s[after_groups] != '.') return false;
    return skip(s, after_groups + 1, digitOrUnderscore) == s.size();
  }
  if (at == s.size() || s[at] != '.') return false;
  at = skip(s, at + 1, digitOrUnderscore);
  return skipExponent(s, at) == s.size();
}

bool isInt(const std::string& s) {
  const std::size_t sign = skipSign(s);
  const std::string p = s.substr(sign);
  if (p.empty()) return false;
  auto all = [&](std::size_t from, auto ok) { return from < p.size() && skip(p, from, ok) == p.size(); };
  if (p.compare(0, 2, "0b") == 0) return all(2, [](char c) { return c == '0' || c == '1' || c == '_'; });
  if (p.compare(0, 2, "0x") == 0) {
    return all(2, [](char c) {
      return isDigit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F') || c == '_';
    });
  }
  if (p == "0") return true;
  if (p[0] == '0') return all(1, [](char c) { return (c >= '0' && c <= '7') || c == '_'; });
  if (p[0] < '1' || p[0] > '9') return false;
  const std::size_t at = skip(p, 1, [](char c) { return isDigit(c) || c == '_'; });
  return at == p.size() || skipSexagesimal(p, at) == p.size();
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
    if (!isBool(text)) fail(name, "'" + text + "' is not a boolean");
    return XmlRpcValue(boolValue(text));
  }
  if (tag != "?") fail(name, "unsupported tag " + tag + " (" + where(node, file) + ")");
  if (isBool(text)) return XmlRpcValue(boolValue(text));
  if (isFloat(text)) return floatValue(text);
  if (isInt(text)) return intValue(text, name);
  if (isNull(text)) fail(name, "has no value (" + where(node, file) + ")");
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
