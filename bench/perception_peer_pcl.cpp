// The PCL peer of bench/perception_bench.cpp: the pipeline PCL's tutorials and most ROS users
// build for "cloud to clusters" (transform, crop box, voxel grid, Euclidean clusters on a
// kd-tree), with PCL's defaults everywhere except the settings shared with ours.

#include <chrono>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/common/transforms.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include "perception_peers.hpp"

namespace perception_peers {

const char* const PclPeer::kStages[4] = {"transformPointCloud", "CropBox", "VoxelGrid",
                                         "KdTree + EuclideanClusterExtraction"};

struct PclPeer::Impl {
  Settings settings;
  Eigen::Affine3f sensor_to_fixed;
  pcl::PointCloud<pcl::PointXYZ>::Ptr input{new pcl::PointCloud<pcl::PointXYZ>};
  pcl::PointCloud<pcl::PointXYZ>::Ptr fixed{new pcl::PointCloud<pcl::PointXYZ>};
  pcl::PointCloud<pcl::PointXYZ>::Ptr cropped{new pcl::PointCloud<pcl::PointXYZ>};
  pcl::PointCloud<pcl::PointXYZ>::Ptr voxels{new pcl::PointCloud<pcl::PointXYZ>};
  std::vector<pcl::PointIndices> clusters;
};

PclPeer::PclPeer(const Frame& frame, const Settings& settings) : impl_(new Impl) {
  impl_->settings = settings;
  impl_->sensor_to_fixed.matrix() = Eigen::Map<const Eigen::Matrix4f>(frame.sensor_to_fixed);
  auto& in = *impl_->input;
  in.width = static_cast<std::uint32_t>(frame.width);
  in.height = static_cast<std::uint32_t>(frame.height);
  in.is_dense = false;  // NaNs for no return, as a depth camera's organised cloud has
  in.points.resize(static_cast<std::size_t>(frame.width) * frame.height);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    in.points[i].x = frame.xyz[3 * i];
    in.points[i].y = frame.xyz[3 * i + 1];
    in.points[i].z = frame.xyz[3 * i + 2];
  }
}

PclPeer::~PclPeer() { delete impl_; }

Result PclPeer::run() {
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  Impl& m = *impl_;
  const Settings& s = m.settings;
  Result r;
  const auto t0 = Clock::now();
  // NaNs pass through the transform (and stay NaN); the crop box drops them.
  pcl::transformPointCloud(*m.input, *m.fixed, m.sensor_to_fixed);
  const auto t1 = Clock::now();
  pcl::CropBox<pcl::PointXYZ> crop;
  crop.setInputCloud(m.fixed);
  crop.setMin(Eigen::Vector4f(s.lower[0], s.lower[1], std::max(s.lower[2], s.floor_cut), 1.0f));
  crop.setMax(Eigen::Vector4f(s.upper[0], s.upper[1], s.upper[2], 1.0f));
  crop.filter(*m.cropped);
  const auto t2 = Clock::now();
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(m.cropped);
  grid.setLeafSize(s.voxel, s.voxel, s.voxel);
  grid.filter(*m.voxels);
  const auto t3 = Clock::now();
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(m.voxels);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(s.cluster_tolerance);
  ec.setMinClusterSize(s.min_cluster_size);
  ec.setSearchMethod(tree);
  ec.setInputCloud(m.voxels);
  m.clusters.clear();
  ec.extract(m.clusters);
  const auto t4 = Clock::now();
  r.stage_ms[0] = ms(t1 - t0);
  r.stage_ms[1] = ms(t2 - t1);
  r.stage_ms[2] = ms(t3 - t2);
  r.stage_ms[3] = ms(t4 - t3);
  r.total_ms = ms(t4 - t0);
  r.points = static_cast<std::int64_t>(m.cropped->size());
  r.voxels = static_cast<std::int64_t>(m.voxels->size());
  r.clusters = static_cast<int>(m.clusters.size());
  return r;
}

}  // namespace perception_peers
