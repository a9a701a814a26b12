#include "workspace_proximity/replay/replay_options.hpp"

#include <cmath>
#include <cstdlib>

namespace workspace_proximity {

const char* replayUsage() {
  return "usage: replay_bag BAG [--config FILE.yaml]... [--urdf FILE] [--out DIR]\n"
         "                  [--input-topic TOPIC] [--rate-factor X | --as-fast-as-possible]\n"
         "                  [--no-report]\n"
         "\n"
         "Replays a recorded bag (tf, tf_static, tracked boxes) through the proximity monitor's\n"
         "own pipeline, in bag time, and writes DIR/events.csv, DIR/cycles.csv, DIR/summary.json\n"
         "and DIR/report.html.\n"
         "\n"
         "  --config FILE.yaml   the node's parameters (its private namespace), as for\n"
         "                       <rosparam command=\"load\">; several files are merged in order\n"
         "  --urdf FILE          the robot description (robot bodies from its collision elements)\n"
         "  --out DIR            output folder (default ./replay-<bag name>)\n"
         "  --input-topic TOPIC  the tracker topic when ~input_topics is empty\n"
         "                       (default tracked_objects, as the node's input_topic remap)\n"
         "  --rate-factor X      paced at X times real time (the results do not change)\n"
         "  --as-fast-as-possible  not paced (the default)\n"
         "  --no-report          CSV and JSON only, no report.html\n"
         "\n"
         "Exit status: 0 done; 2 bad command line; 3 configuration or URDF unusable; 4 bag\n"
         "unreadable, unindexed, truncated or without the input topic; 5 replayed, but a frame\n"
         "had no tf in the bag; 6 output not written.\n";
}

bool parseReplayOptions(const std::vector<std::string>& args, ReplayOptions* out,
                        std::string* error) {
  ReplayOptions o;
  bool paced = false, unpaced = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string value;
    bool has_value = false;
    std::string name = a;
    const auto eq = a.find('=');
    if (a.compare(0, 2, "--") == 0 && eq != std::string::npos) {
      name = a.substr(0, eq);
      value = a.substr(eq + 1);
      has_value = true;
    }
    auto take = [&](std::string* into) {
      if (has_value) {
        *into = value;
        return true;
      }
      if (i + 1 >= args.size()) {
        *error = name + " needs a value";
        return false;
      }
      *into = args[++i];
      return true;
    };
    if (name == "-h" || name == "--help") {
      o.help = true;
    } else if (name == "--config") {
      std::string file;
      if (!take(&file)) return false;
      o.config_files.push_back(file);
    } else if (name == "--urdf") {
      if (!take(&o.urdf)) return false;
    } else if (name == "--out") {
      if (!take(&o.out_dir)) return false;
    } else if (name == "--input-topic") {
      if (!take(&o.input_topic)) return false;
      if (o.input_topic.empty()) {
        *error = "--input-topic must not be empty";
        return false;
      }
    } else if (name == "--rate-factor") {
      std::string text;
      if (!take(&text)) return false;
      char* end = nullptr;
      o.rate_factor = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(o.rate_factor) || o.rate_factor <= 0.0) {
        *error = "--rate-factor wants a positive number, got '" + text + "'";
        return false;
      }
      paced = true;
    } else if (name == "--as-fast-as-possible") {
      unpaced = true;
    } else if (name == "--no-report") {
      o.report = false;
    } else if (a.compare(0, 1, "-") == 0 && a.size() > 1) {
      *error = "unknown option " + a;
      return false;
    } else if (o.bag.empty()) {
      o.bag = a;
    } else {
      *error = "one bag at a time (got " + o.bag + " and " + a + ")";
      return false;
    }
  }
  if (paced && unpaced) {
    *error = "--rate-factor and --as-fast-as-possible exclude each other";
    return false;
  }
  if (o.bag.empty() && !o.help) {
    *error = "no bag given";
    return false;
  }
  if (o.out_dir.empty() && !o.bag.empty()) {
    std::string name = o.bag.substr(o.bag.find_last_of('/') + 1);
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".bag") == 0) name.resize(name.size() - 4);
    o.out_dir = "replay-" + name;
  }
  *out = o;
  return true;
}

std::string resolveTopic(const std::string& name) {
  if (name.empty() || name[0] == '/') return name;
  if (name[0] == '~') return "/proximity_monitor/" + name.substr(name[1] == '/' ? 2 : 1);
  return "/" + name;
}

}  // namespace workspace_proximity
