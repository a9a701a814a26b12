// load_generator as a nodelet (workspace_proximity/LoadGeneratorNodelet), for the latency
// benchmark's nodelet row: in the monitor's manager, its arrays reach the monitor without
// serialisation. Publishes from its own thread; receipts come on the multi-threaded queue.

#include <memory>
#include <thread>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "workspace_proximity/tools/load_generator.hpp"

namespace workspace_proximity {

class LoadGeneratorNodelet : public nodelet::Nodelet {
 public:
  ~LoadGeneratorNodelet() override {
    if (thread_.joinable()) thread_.join();
  }

 private:
  void onInit() override {
    generator_ = std::make_unique<LoadGenerator>(getMTNodeHandle(), getPrivateNodeHandle(), true);
    thread_ = std::thread([this] { generator_->run(); });
  }

  std::unique_ptr<LoadGenerator> generator_;
  std::thread thread_;
};

}  // namespace workspace_proximity

PLUGINLIB_EXPORT_CLASS(workspace_proximity::LoadGeneratorNodelet, nodelet::Nodelet)
