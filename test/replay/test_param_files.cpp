// The files that repeat the parameter table, checked against it (param_table.hpp):
// - cfg/ProximityMonitor.cfg, as dynamic_reconfigure generated ProximityMonitorConfig from it:
//   every slider is a live row (or a live label setting in the default_, person_ or robot_
//   group) with the row's default, min and max, and every live row has its slider;
// - config/*.yaml, loaded as the replay loads them: no unknown key, valid, and
//   config/proximity_monitor.yaml lists every plain row (not a structure) at its default,
//   with the row's range where a comment gives one ("(0.1 .. 1000)");
// - the docs' parameter tables (docs/node.md and docs/ssm.md, or README.md before the docs
//   split): every row documented, no row documented that is not one, and each default and
//   "(<min> to <max>)" range given there equal to the row's.
// Here rather than under test/ros because the YAML files are read with the replay's loader.

#include <gtest/gtest.h>

#include <dirent.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <boost/any.hpp>
#include <workspace_proximity/ProximityMonitorConfig.h>

#include "workspace_proximity/rules/param_table.hpp"
#include "workspace_proximity/replay/yaml_params.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace wp = workspace_proximity;
using Config = wp::ProximityMonitorConfig;
using XmlRpc::XmlRpcValue;

namespace {

const std::string kSource = WP_SOURCE_DIR "/";

bool isNumber(const wp::ParamRow& row) {
  return row.member.type == wp::ParamType::kNumber || row.member.type == wp::ParamType::kInteger;
}

// The config's value of slider `d` in `c`, as a double (a bool as 0 or 1).
double valueOf(const Config::AbstractParamDescriptionConstPtr& d, const Config& c) {
  boost::any v;
  d->getValue(c, v);
  if (d->type == "bool") return boost::any_cast<bool>(v) ? 1.0 : 0.0;
  return boost::any_cast<double>(v);
}

// What a slider should be: its default, range and type.
struct Expected {
  std::string what;  // the row, for messages
  double value;
  double min;
  double max;
  bool flag;
};

// Every slider the table asks for, by its name in the .cfg.
std::map<std::string, Expected> expectedSliders() {
  std::map<std::string, Expected> out;
  const wp::MonitorParams defaults;
  wp::MonitorParams& d = const_cast<wp::MonitorParams&>(defaults);
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (row.tuning != wp::Tuning::kLive || row.member.type == wp::ParamType::kStructure) continue;
    std::string name = row.name;
    std::replace(name.begin(), name.end(), '/', '_');
    if (row.member.type == wp::ParamType::kBool) {
      out[name] = {row.name, row.member.flag(d) ? 1.0 : 0.0, 0, 0, true};
    } else {
      out[name] = {row.name, wp::numberOf(row, defaults), row.min, row.max, false};
    }
  }
  const wp::LabelSettings label;
  for (const wp::LabelRow& row : wp::labelTable()) {
    if (row.tuning != wp::Tuning::kLive) continue;
    for (const char* group : {"default", "person", "robot"}) {
      if (row.track_only && std::string(group) == "robot") continue;
      out[std::string(group) + "_" + row.key] = {std::string(group) + " label's " + row.key,
                                                 label.*row.member, row.min, row.max, false};
    }
  }
  return out;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool exists(const std::string& path) { return std::ifstream(path).good(); }

// ---- the docs' tables ----

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

// The cells of a table line "| a | b | c |" (an escaped "\|" stays in its cell).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += "\\|";
      ++i;
    } else if (line[i] == '|') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return out;
}

// The `backticked` words of a cell.
std::vector<std::string> codeSpans(const std::string& cell) {
  std::vector<std::string> out;
  for (std::size_t a = cell.find('`'); a != std::string::npos;) {
    const std::size_t b = cell.find('`', a + 1);
    if (b == std::string::npos) break;
    out.push_back(cell.substr(a + 1, b - a - 1));
    a = cell.find('`', b + 1);
  }
  return out;
}

// One line of a parameter table: the names of its first cell, its default and meaning cells.
struct DocEntry {
  std::string file;
  std::vector<std::string> names;
  std::string default_text;
  std::string meaning;
};

// Every line of the tables whose header starts "| parameter | default |" in `file`.
std::vector<DocEntry> docEntries(const std::string& file) {
  std::vector<DocEntry> out;
  std::istringstream text(readFile(file));
  bool in_table = false;
  for (std::string line; std::getline(text, line);) {
    line = trim(line);
    if (line.empty() || line[0] != '|') {
      in_table = false;
      continue;
    }
    const std::vector<std::string> c = cells(line);
    if (c.size() >= 3 && c[0] == "parameter" && c[1] == "default") {
      in_table = true;
      continue;
    }
    if (!in_table || c.size() < 3 || c[0].rfind("---", 0) == 0) continue;
    DocEntry e{file, {}, c[1], c[2]};
    for (std::string name : codeSpans(c[0])) {
      if (!name.empty() && name[0] == '~') name.erase(0, 1);
      e.names.push_back(name);
    }
    out.push_back(e);
  }
  return out;
}

// The files holding the parameter tables: the docs' pages once they exist, the README before.
std::vector<std::string> docFiles() {
  std::vector<std::string> out;
  for (const char* f : {"docs/node.md", "docs/ssm.md"}) {
    if (exists(kSource + f)) out.push_back(kSource + f);
  }
  if (out.empty()) out.push_back(kSource + "README.md");
  return out;
}

bool parseNumber(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

// The "<a> to <b>" of a meaning cell, when it gives one.
bool docRange(const std::string& meaning, double* lo, double* hi) {
  const std::string number_chars = "0123456789.eE+-";
  for (std::size_t at = meaning.find(" to "); at != std::string::npos;
       at = meaning.find(" to ", at + 1)) {
    std::size_t a = at;
    while (a > 0 && number_chars.find(meaning[a - 1]) != std::string::npos) --a;
    std::size_t b = at + 4;
    while (b < meaning.size() && number_chars.find(meaning[b]) != std::string::npos) ++b;
    if (parseNumber(meaning.substr(a, at - a), lo) && parseNumber(meaning.substr(at + 4, b - at - 4), hi)) {
      return true;
    }
  }
  return false;
}

// Whether the docs' default `text` states `row`'s default. "see ..." states nothing: true.
::testing::AssertionResult sameDefault(const wp::ParamRow& row, const std::string& text) {
  if (text.rfind("see ", 0) == 0) return ::testing::AssertionSuccess();
  wp::MonitorParams defaults;
  const wp::ParamMember& m = row.member;
  const std::vector<std::string> code = codeSpans(text);
  const std::string literal = code.size() == 1 ? code[0] : text;
  bool same = false;
  double number = 0.0;
  switch (m.type) {
    case wp::ParamType::kNumber:
    case wp::ParamType::kInteger:
      same = parseNumber(literal, &number) && number == wp::numberOf(row, defaults);
      break;
    case wp::ParamType::kBool:
      same = literal == (m.flag(defaults) ? "true" : "false");
      break;
    case wp::ParamType::kString:
      same = literal == (m.text(defaults).empty() ? "\"\"" : m.text(defaults));
      break;
    case wp::ParamType::kStringList:
      same = literal == "[]" && m.names(defaults).empty();
      break;
    case wp::ParamType::kPairs:
      same = literal == "[]" && m.pairs(defaults).empty();
      break;
    case wp::ParamType::kStructure:
      same = literal == "[]" && std::string(row.name) == "robot_bodies";
      break;
  }
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "~" << row.name << ": the docs give the default '" << text
                                       << "'";
}

// A label setting's name in the docs ("labels/<l>/max_accel", "labels/<label>/ssm_min_speed"):
// its key, or "" when `name` is no such name.
std::string labelKey(const std::string& name) {
  if (name.rfind("labels/", 0) != 0) return "";
  const std::size_t slash = name.find('/', 7);
  if (slash == std::string::npos) return "";
  return name.substr(slash + 1);
}

}  // namespace

TEST(ParamFiles, TheCfgHasASliderForEachLiveRowWithItsDefaultAndRange) {
  std::map<std::string, Expected> expected = expectedSliders();
  const Config& defaults = Config::__getDefault__();
  const Config& mins = Config::__getMin__();
  const Config& maxs = Config::__getMax__();
  for (const Config::AbstractParamDescriptionConstPtr& d : Config::__getParamDescriptions__()) {
    auto it = expected.find(d->name);
    if (it == expected.end()) {
      ADD_FAILURE() << "cfg/ProximityMonitor.cfg: slider '" << d->name
                    << "' is no live row of param_table.cpp";
      continue;
    }
    const Expected& e = it->second;
    EXPECT_EQ(d->type, e.flag ? "bool" : "double") << d->name;
    EXPECT_EQ(valueOf(d, defaults), e.value) << d->name << ": default of " << e.what;
    if (!e.flag) {
      EXPECT_EQ(valueOf(d, mins), e.min) << d->name << ": min of " << e.what;
      EXPECT_EQ(valueOf(d, maxs), e.max) << d->name << ": max of " << e.what;
    }
    expected.erase(it);
  }
  for (const auto& missing : expected) {
    ADD_FAILURE() << "cfg/ProximityMonitor.cfg has no slider '" << missing.first << "' for "
                  << missing.second.what;
  }
}

TEST(ParamFiles, TheConfigFilesUseKnownKeysAndTheDefaultFileEveryDefault) {
  // The monitor's files: config/*.yaml (cloud_tracker's are in config/cloud_tracker/, read by
  // cloud_tracker, not by the monitor).
  const std::string dir = kSource + "config/";
  std::vector<std::string> files;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string name = e->d_name;
      if (name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0) files.push_back(dir + name);
    }
    ::closedir(d);
  }
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    const XmlRpcValue root = wp::loadYamlParams({file});
    EXPECT_EQ(wp::unknownParams(root), std::vector<std::string>()) << file;
    EXPECT_TRUE(wp::validate(wp::readParams(root)).empty()) << file;
  }

  // The default file lists every plain parameter (not a structure) at its default.
  const std::string file = dir + "proximity_monitor.yaml";
  const XmlRpcValue root = wp::loadYamlParams({file});
  const wp::MonitorParams defaults;
  wp::MonitorParams read = wp::readParams(root);
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (row.member.type == wp::ParamType::kStructure) continue;
    // Present: the row's path in the tree.
    const XmlRpcValue* at = &root;
    std::string name = row.name;
    for (std::size_t slash; at != nullptr && (slash = name.find('/')) != std::string::npos;
         name.erase(0, slash + 1)) {
      const std::string ns = name.substr(0, slash);
      at = at->hasMember(ns) ? &const_cast<XmlRpcValue&>(*at)[ns] : nullptr;
    }
    EXPECT_TRUE(at != nullptr && at->hasMember(name)) << file << ": ~" << row.name << " not listed";
    // At its default: what the file sets is the default struct's value.
    wp::MonitorParams from_file = defaults;
    row.member.copy(read, from_file);
    wp::MonitorParams& d = const_cast<wp::MonitorParams&>(defaults);
    bool same = true;
    switch (row.member.type) {
      case wp::ParamType::kNumber: same = row.member.number(from_file) == row.member.number(d); break;
      case wp::ParamType::kInteger: same = row.member.integer(from_file) == row.member.integer(d); break;
      case wp::ParamType::kBool: same = row.member.flag(from_file) == row.member.flag(d); break;
      case wp::ParamType::kString: same = row.member.text(from_file) == row.member.text(d); break;
      case wp::ParamType::kStringList: same = row.member.names(from_file) == row.member.names(d); break;
      case wp::ParamType::kPairs: same = row.member.pairs(from_file) == row.member.pairs(d); break;
      case wp::ParamType::kStructure: break;
    }
    EXPECT_TRUE(same) << file << ": ~" << row.name << " is not its default";
  }
  // A range in a line's comment, "(<min> .. <max>)", is the row's.
  std::istringstream text(readFile(file));
  std::string ns;  // the namespace of indented keys ("ssm/")
  for (std::string line; std::getline(text, line);) {
    const std::size_t colon = line.find(':');
    const std::size_t hash = line.find('#');
    if (line.empty() || line[0] == '#' || colon == std::string::npos || hash < colon) continue;
    const std::string key = trim(line.substr(0, colon));
    if (line[0] != ' ') ns = trim(line.substr(colon + 1, hash - colon - 1)).empty() ? key + "/" : "";
    const std::string name = line[0] == ' ' ? ns + key : key;
    const std::size_t dots = hash == std::string::npos ? hash : line.find(" .. ", hash);
    if (dots == std::string::npos) continue;
    std::string range = line.substr(line.rfind('(', dots) + 1);
    range = range.substr(0, range.find(')'));
    double lo = 0.0, hi = 0.0;
    const std::size_t sep = range.find(" .. ");
    ASSERT_TRUE(parseNumber(range.substr(0, sep), &lo) && parseNumber(range.substr(sep + 4), &hi))
        << file << ": " << line;
    const wp::ParamRow* row = wp::findParam(name);
    ASSERT_NE(row, nullptr) << file << ": " << line;
    EXPECT_EQ(lo, row->min) << file << ": " << line;
    EXPECT_EQ(hi, row->max) << file << ": " << line;
  }
  // The default label as the struct has it.
  const wp::LabelSettings label;
  for (const wp::LabelRow& row : wp::labelTable()) {
    EXPECT_EQ(read.label("default").*row.member, label.*row.member) << "labels/default/" << row.key;
  }
}

TEST(ParamFiles, TheDocsDocumentEveryRowWithItsDefaultAndRange) {
  std::vector<DocEntry> entries;
  for (const std::string& file : docFiles()) {
    const std::vector<DocEntry> more = docEntries(file);
    EXPECT_FALSE(more.empty()) << file << ": no table headed | parameter | default | meaning |";
    entries.insert(entries.end(), more.begin(), more.end());
  }
  std::set<std::string> documented;      // row names
  std::set<std::string> documented_keys; // label settings
  std::string labels_meaning;            // the meaning of ~labels, which may name settings
  for (const DocEntry& e : entries) {
    for (const std::string& name : e.names) {
      if (name.size() >= 3 && name.compare(name.size() - 3, 3, "...") == 0) continue;  // ssm/...
      const std::string where = e.file + ": `" + name + "`";
      double lo = 0.0, hi = 0.0;
      const bool ranged = docRange(e.meaning, &lo, &hi);
      if (const wp::ParamRow* row = wp::findParam(name)) {
        documented.insert(name);
        if (name == "labels") labels_meaning += e.meaning;
        EXPECT_TRUE(sameDefault(*row, e.default_text)) << where;
        if (ranged) {
          EXPECT_TRUE(isNumber(*row)) << where << ": a range for a row that is no number";
          EXPECT_EQ(lo, row->min) << where << ": the docs' lower end";
          EXPECT_EQ(hi, row->max) << where << ": the docs' upper end";
        }
      } else if (const wp::LabelRow* row = wp::findLabelSetting(labelKey(name))) {
        documented_keys.insert(row->key);
        double value = 0.0;
        EXPECT_TRUE(e.default_text.rfind("see ", 0) == 0 ||
                    (parseNumber(e.default_text, &value) && value == wp::LabelSettings().*row->member))
            << where << ": the docs give the default '" << e.default_text << "'";
        if (ranged) {
          EXPECT_EQ(lo, row->min) << where << ": the docs' lower end";
          EXPECT_EQ(hi, row->max) << where << ": the docs' upper end";
        }
      } else {
        ADD_FAILURE() << where << " is documented but no parameter of param_table.cpp";
      }
    }
  }
  for (const wp::ParamRow& row : wp::paramTable()) {
    EXPECT_EQ(documented.count(row.name), 1u) << "~" << row.name << " is not in the docs' tables";
  }
  // A label setting: its own line (labels/<label>/<key>) or named in the line of ~labels.
  const std::vector<std::string> named = codeSpans(labels_meaning);
  for (const wp::LabelRow& row : wp::labelTable()) {
    EXPECT_TRUE(documented_keys.count(row.key) == 1 ||
                std::find(named.begin(), named.end(), row.key) != named.end())
        << "labels/<label>/" << row.key << " is not in the docs' tables";
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
