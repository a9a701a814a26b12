// The node's predict load through ProximityWorld alone, for comparing versions of the core
// (bench/experiments/bench-predict-ab builds it against each): load_generator's walkers (same seed,
// cell 3 sqrt(N) m, people 0.5 x 0.5 x 1.8 m and every tenth a 2.4 x 1.2 x 2.0 m forklift at
// 0.3-1.5 m/s) with the node's default margin (0.1 m, no configuration loaded), horizon 2 s,
// 30 Hz. Uses only the API every version has (addBody, setMotion, predict), so it builds
// against old trees too. Prints one line: median / p10 / p90 of predict() in µs, events.
// Usage: predict_ab_driver [COUNT=1000] [CYCLES=600] [id|yaw][-cold][-idle]
//   id:  the load generator's boxes (identity orientation, as scripts/bench-node sends them);
//   yaw: each box turned to its heading with a little noise that changes every cycle, as a
//        tracker reports them (no two cycles give the same orientation).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>
#include "workspace_proximity/proximity_world.hpp"
namespace wp = workspace_proximity;
int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 1000;
  const int cycles = argc > 2 ? std::atoi(argv[2]) : 600;
  const bool yaw = argc > 3 && std::string(argv[3]).find("yaw") != std::string::npos;
  // "cold" (e.g. "id-cold"): 16 MB written between cycles (not timed), so that every cycle
  // starts with caches holding none of the world, as in the node, whose cycles are 33 ms apart
  // with other threads and processes running in between.
  const bool cold = argc > 3 && std::string(argv[3]).find("cold") != std::string::npos;
  // "idle" (e.g. "id-idle"): 30 ms asleep between cycles, as the node's timer leaves the core.
  const bool idle = argc > 3 && std::string(argv[3]).find("idle") != std::string::npos;
  std::vector<char> flush(cold ? (16u << 20) : 0u);
  wp::ProximityWorld world;
  std::mt19937 rng(0);
  const double cell = std::round(30.0 * std::sqrt(double(count))) / 10.0;
  std::uniform_real_distribution<double> pos(-cell / 2, cell / 2), dir(0, 2 * M_PI), speed(0.3, 1.5);
  struct W { double x, y, vx, vy; wp::BodyHandle h; };
  std::vector<W> ws(count);
  for (int i = 0; i < count; ++i) {
    W& w = ws[i];
    const double a = dir(rng), s = speed(rng);
    w.x = pos(rng); w.y = pos(rng); w.vx = s * std::cos(a); w.vy = s * std::sin(a);
    const bool f = i % 10 == 0;
    wp::BodyDesc d;
    d.id = "walker_" + std::to_string(i);
    d.label = f ? "forklift" : "person";
    d.shape = wp::Shape::box(f ? Eigen::Vector3d(1.2, 0.6, 1.0) : Eigen::Vector3d(0.25, 0.25, 0.9));
    d.margin = 0.1;
    w.h = world.addBody(d, wp::BodyMotion());
  }
  std::vector<double> us;
  double events = 0;
  for (int c = 0; c < 30 + cycles; ++c) {
    for (W& w : ws) {
      w.x += w.vx / 30.0; w.y += w.vy / 30.0;
      if (std::abs(w.x) > cell / 2) w.vx = -w.vx;
      if (std::abs(w.y) > cell / 2) w.vy = -w.vy;
      wp::BodyMotion m;
      m.position = Eigen::Vector3d(w.x, w.y, 0.0);
      m.linear_velocity = Eigen::Vector3d(w.vx, w.vy, 0.0);
      if (yaw) {
        const double heading = std::atan2(w.vy, w.vx) + 0.01 * std::sin(0.7 * c + (&w - ws.data()));
        m.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()));
      }
      world.setMotion(w.h, m);
    }
    for (std::size_t k = 0; k < flush.size(); k += 64) flush[k] = static_cast<char>(c + k);
    if (idle) std::this_thread::sleep_for(std::chrono::milliseconds(30));
    const auto t0 = std::chrono::steady_clock::now();
    const auto& ev = world.predict(2.0);
    const double t = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    if (c >= 30) { us.push_back(t); events += double(ev.size()) / cycles; }
  }
  std::sort(us.begin(), us.end());
  std::printf("count %d cycles %d orientation %s%s predict median %.1f us p10 %.1f p90 %.1f events %.1f\n", count, cycles, yaw ? "yaw" : "id", cold ? " (cold caches)" : idle ? " (30 ms idle between cycles)" : "",
              us[us.size() / 2], us[us.size() / 10], us[us.size() * 9 / 10], events);
}
