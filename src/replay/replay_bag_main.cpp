// replay_bag: a recorded bag through the proximity monitor's pipeline, offline and in bag time;
// writes the events, the cycles and a summary, then the HTML report (tools/replay_report.py).
// No master, no network. See replayUsage() for the command line and the exit statuses.

#include <sys/wait.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <ros/time.h>

#include "workspace_proximity/replay/bag_input.hpp"
#include "workspace_proximity/replay/bag_replay.hpp"
#include "workspace_proximity/replay/replay_options.hpp"
#include "workspace_proximity/replay/replay_output.hpp"
#include "workspace_proximity/replay/robot_from_file.hpp"
#include "workspace_proximity/replay/yaml_params.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace wp = workspace_proximity;

namespace {

// The configuration as the node reads and checks it; throws ReplayError (kConfig) with the
// node's messages ("invalid parameter ~name: ...").
wp::MonitorParams loadParams(const std::vector<std::string>& files) {
  wp::MonitorParams params;
  try {
    params = wp::readParams(wp::loadYamlParams(files));
  } catch (const std::exception& e) {
    throw wp::ReplayError(wp::ReplayError::kConfig, std::string("invalid parameter ") + e.what());
  }
  const std::vector<std::string> errors = wp::validate(params);
  if (!errors.empty()) {
    std::string all;
    for (const std::string& e : errors) all += (all.empty() ? "" : "\n") + ("invalid parameter " + e);
    throw wp::ReplayError(wp::ReplayError::kConfig, all);
  }
  return params;
}

// The report generator: installed (and relayed in the devel space) next to this executable.
std::string reportScript() {
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0) return std::string();
  std::string dir(self, static_cast<std::size_t>(n));
  dir.resize(dir.find_last_of('/'));
  const std::string script = dir + "/replay_report.py";
  return ::access(script.c_str(), X_OK) == 0 ? script : std::string();
}

// Runs the report generator on `out_dir`; returns its exit status (127: not found).
int runReport(const std::string& out_dir) {
  const std::string script = reportScript();
  if (script.empty()) {
    std::fprintf(stderr, "replay_bag: replay_report.py not found next to the executable; "
                         "no report.html (run tools/replay_report.py %s)\n", out_dir.c_str());
    return 127;
  }
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    // Debian's interpreter, which has matplotlib, whatever python3 comes first on PATH (a
    // virtual environment's may not); the script's own line otherwise.
    const char* python = "/usr/bin/python3";
    if (::access(python, X_OK) == 0) {
      ::execl(python, python, script.c_str(), out_dir.c_str(), static_cast<char*>(nullptr));
    }
    ::execl(script.c_str(), script.c_str(), out_dir.c_str(), static_cast<char*>(nullptr));
    std::perror("replay_bag: cannot run replay_report.py");
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int replay(const wp::ReplayOptions& options) {
  wp::ReplaySetup setup;
  setup.params = loadParams(options.config_files);
  std::vector<std::string> topics = setup.params.input_topics;
  if (topics.empty()) topics.push_back(options.input_topic.empty() ? "tracked_objects" : options.input_topic);
  for (const std::string& t : topics) setup.topics.push_back(wp::resolveTopic(t));
  setup.qualify = !setup.params.input_topics.empty();

  wp::ReplayInfo info;
  info.bag = options.bag;
  info.config_files = options.config_files;
  info.urdf = options.urdf;
  try {
    wp::RobotDescription robot = wp::robotBodiesFromFile(options.urdf, setup.params, &info.warnings);
    if (setup.params.require_all_links && !robot.unmodelled.empty()) {
      throw std::runtime_error(std::to_string(robot.unmodelled.size()) +
                               " URDF collision elements cannot be modelled and ~require_all_links "
                               "is true: " + robot.unmodelled.front());
    }
    setup.robot = std::move(robot.bodies);
    if (!options.urdf.empty()) {
      std::ifstream in(options.urdf);
      setup.urdf_xml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    // As in the node: every cycle's status is DEGRADED naming each.
    setup.permanent_issues = robot.unmodelled;
  } catch (const std::exception& e) {
    throw wp::ReplayError(wp::ReplayError::kConfig, e.what());
  }
  if (options.urdf.empty() && setup.params.use_robot_description) {
    info.warnings.push_back("no --urdf: robot bodies from ~robot_bodies only");
  }

  wp::BagInput bag(options.bag, setup.topics);
  info.input = &bag;
  info.setup = &setup;
  wp::ReplayWriter writer(options.out_dir, bag.begin());
  wp::BagReplay replay(setup);
  const wp::ReplayStats stats = replay.run(&bag, &writer, options.rate_factor);
  writer.finish(stats, info);

  std::printf("%s", wp::summaryText(stats, info).c_str());
  std::printf("  output: %s/{events.csv, cycles.csv, summary.json}\n", options.out_dir.c_str());
  int status = 0;
  if (options.report && runReport(options.out_dir) != 0) {
    std::fprintf(stderr, "replay_bag: the report generator failed; the CSV files are complete\n");
    status = wp::ReplayError::kOutput;
  }
  if (!stats.missing_frames.empty()) {
    for (const std::string& m : stats.missing_frames) {
      std::fprintf(stderr, "replay_bag: bag %s: %s\n", options.bag.c_str(), m.c_str());
    }
    return wp::ReplayError::kIncomplete;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  ros::Time::init();  // wall time until the replay sets the bag's
  wp::ReplayOptions options;
  std::string error;
  if (!wp::parseReplayOptions(std::vector<std::string>(argv + 1, argv + argc), &options, &error)) {
    std::fprintf(stderr, "replay_bag: %s\n\n%s", error.c_str(), wp::replayUsage());
    return wp::ReplayError::kUsage;
  }
  if (options.help) {
    std::printf("%s", wp::replayUsage());
    return 0;
  }
  try {
    return replay(options);
  } catch (const wp::ReplayError& e) {
    std::fprintf(stderr, "replay_bag: %s\n", e.what());
    return e.exitCode();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "replay_bag: unexpected error: %s\n", e.what());
    return 1;
  }
}
