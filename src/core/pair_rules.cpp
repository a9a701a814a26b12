#include "workspace_proximity/pair_rules.hpp"

#include <stdexcept>

namespace workspace_proximity {

bool BodySelector::matches(const BodyDesc& body) const {
  switch (kind) {
    case Kind::kAny:
      return true;
    case Kind::kGroup:
      return body.group == group;
    case Kind::kLabel:
      return body.label == value;
    case Kind::kId:
      return body.id == value;
  }
  return false;
}

BodySelector BodySelector::parse(const std::string& text) {
  BodySelector s;
  if (text == "*") return s;
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon + 1 >= text.size()) {
    throw std::invalid_argument("pair rule selector '" + text +
                                "': expected '*', 'group:robot|object', 'label:<label>' or "
                                "'id:<id>'");
  }
  const std::string kind = text.substr(0, colon);
  s.value = text.substr(colon + 1);
  if (kind == "group") {
    s.kind = Kind::kGroup;
    if (s.value == "robot") {
      s.group = BodyGroup::kRobot;
    } else if (s.value == "object") {
      s.group = BodyGroup::kObject;
    } else {
      throw std::invalid_argument("pair rule selector '" + text +
                                  "': group must be 'robot' or 'object'");
    }
  } else if (kind == "label") {
    s.kind = Kind::kLabel;
  } else if (kind == "id") {
    s.kind = Kind::kId;
  } else {
    throw std::invalid_argument("pair rule selector '" + text + "': unknown kind '" + kind +
                                "' (use group, label or id)");
  }
  return s;
}

std::string BodySelector::toString() const {
  switch (kind) {
    case Kind::kAny:
      return "*";
    case Kind::kGroup:
      return std::string("group:") + (group == BodyGroup::kRobot ? "robot" : "object");
    case Kind::kLabel:
      return "label:" + value;
    case Kind::kId:
      return "id:" + value;
  }
  return "*";
}

PairRules::PairRules() { add("group:robot", "group:robot", false); }

PairRules PairRules::allowAll() {
  PairRules rules;
  rules.rules_.clear();
  return rules;
}

void PairRules::add(const std::string& first, const std::string& second, bool allow) {
  add(PairRule{BodySelector::parse(first), BodySelector::parse(second), allow});
}

bool PairRules::allowed(const BodyDesc& a, const BodyDesc& b) const {
  // Last match wins, so later, more specific rules override earlier general ones.
  for (auto it = rules_.rbegin(); it != rules_.rend(); ++it) {
    const bool forward = it->first.matches(a) && it->second.matches(b);
    const bool backward = it->first.matches(b) && it->second.matches(a);
    if (forward || backward) return it->allow;
  }
  return true;
}

}  // namespace workspace_proximity
