#pragma once
/// Which body pairs are checked: an ordered rule table by group, label or id.

#include <string>
#include <vector>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

/// Matches bodies by one property. Text form (see parse()):
/// "*" any body, "group:robot" / "group:object", "label:<label>", "id:<id>".
struct BodySelector {
  enum class Kind { kAny, kGroup, kLabel, kId };
  Kind kind = Kind::kAny;
  BodyGroup group = BodyGroup::kObject;
  std::string value;

  bool matches(const BodyDesc& body) const;
  /// Parses the text form; throws std::invalid_argument naming the bad text.
  static BodySelector parse(const std::string& text);
  std::string toString() const;
};

struct PairRule {
  BodySelector first;
  BodySelector second;
  bool allow = false;
};

/// Rules are symmetric (a rule for (x, y) also matches (y, x)); the last matching rule
/// wins; with no match a pair is allowed. The default table denies robot-robot pairs.
class PairRules {
 public:
  /// The default: one rule, deny group:robot with group:robot.
  PairRules();
  /// No rules at all: every pair is checked.
  static PairRules allowAll();

  void add(const PairRule& rule) { rules_.push_back(rule); }
  /// Convenience: add(parse(first), parse(second), allow).
  void add(const std::string& first, const std::string& second, bool allow);
  bool allowed(const BodyDesc& a, const BodyDesc& b) const;
  const std::vector<PairRule>& rules() const { return rules_; }

 private:
  std::vector<PairRule> rules_;
};

}  // namespace workspace_proximity
