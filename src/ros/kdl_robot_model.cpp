#include "workspace_proximity/ros/kdl_robot_model.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf/model.h>

namespace workspace_proximity {
namespace {

Eigen::Isometry3d toEigen(const KDL::Frame& f) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    out.translation()(r) = f.p(r);
    for (int c = 0; c < 3; ++c) out.linear()(r, c) = f.M(r, c);
  }
  return out;
}

}  // namespace

struct KdlRobotModel::Impl {
  KDL::Tree tree;
};

KdlRobotModel::KdlRobotModel(const std::string& urdf_xml) : impl_(std::make_unique<Impl>()) {
  urdf::Model urdf;
  if (!urdf.initString(urdf_xml)) throw std::runtime_error("the URDF does not parse");
  if (!kdl_parser::treeFromUrdfModel(urdf, impl_->tree)) {
    throw std::runtime_error("kdl_parser cannot build a tree from the URDF");
  }
  const KDL::SegmentMap::const_iterator root = impl_->tree.getRootSegment();
  root_ = root->first;
  // Parent-first walk. Per entry: the chain of movable joints above it, and for the reach
  // bounds the segment's largest offset from its parent's frame (the fixed part of its tip
  // plus, for a prismatic joint, its travel).
  struct Walk {
    KDL::SegmentMap::const_iterator it;
    int parent;
  };
  std::vector<Walk> stack{{root, -1}};
  std::vector<std::vector<int>> chains;
  std::vector<double> hop;  // per entry: bound on |its origin - its parent's origin|
  while (!stack.empty()) {
    const Walk w = stack.back();
    stack.pop_back();
    Entry e;
    e.parent = w.parent;
    const int self = static_cast<int>(order_.size());
    std::vector<int> chain = w.parent >= 0 ? chains[static_cast<std::size_t>(w.parent)] : std::vector<int>();
    double length = 0.0;
    if (w.parent >= 0) {
      e.segment = &GetTreeElementSegment(w.it->second);
      const KDL::Joint& joint = e.segment->getJoint();
      length = e.segment->pose(0.0).p.Norm();
      const urdf::JointConstSharedPtr uj = urdf.getJoint(joint.getName());
      const bool mimic = uj && uj->mimic;
      if (joint.getType() != KDL::Joint::None && uj && !mimic) {
        KinematicJoint kj;
        kj.name = joint.getName();
        if (uj->type == urdf::Joint::CONTINUOUS) {
          kj.type = JointType::kContinuous;
          kj.limited = false;
        } else {
          kj.type = uj->type == urdf::Joint::PRISMATIC ? JointType::kPrismatic : JointType::kRevolute;
          kj.limited = uj->limits && uj->limits->upper > uj->limits->lower;
          if (kj.limited) {
            kj.lower = uj->limits->lower;
            kj.upper = uj->limits->upper;
          }
        }
        if (kj.type == JointType::kPrismatic) {
          // The child's origin slides along the axis: its offset is at most the tip's plus
          // the travel (unbounded without limits: such a joint is not modelled).
          length += kj.limited ? std::max(std::abs(kj.lower), std::abs(kj.upper))
                               : std::numeric_limits<double>::infinity();
        }
        if (std::isfinite(length)) {
          e.joint = static_cast<int>(joints_.size());
          joints_.push_back(kj);
          chain.push_back(e.joint);
        } else {
          chain.push_back(-1);  // not modelled: the links below are left out
        }
      } else if (joint.getType() != KDL::Joint::None) {
        chain.push_back(-1);  // mimic joint: not modelled
      }
    }
    hop.push_back(length);
    bool modelled = true;
    for (int j : chain) modelled = modelled && j >= 0;
    if (w.parent >= 0 && !chain.empty() && modelled) {
      KinematicLink link;
      link.name = w.it->first;
      link.chain = chain;
      // Reach from joint k's axis point (its child's origin) and from the root's origin to
      // this link's origin: at most the sum of the hops between (triangle inequality).
      double sum = 0.0;
      std::vector<double> from_here;  // entries from this one up to the root
      for (int at = self; at >= 0;) {
        from_here.push_back(sum);
        const int up = at == self ? e.parent : order_[static_cast<std::size_t>(at)].parent;
        sum += at == self ? length : hop[static_cast<std::size_t>(at)];
        at = up;
      }
      link.root_reach = sum;
      // Joint k's child entry: walk up again, matching joints.
      link.reach.assign(chain.size(), 0.0);
      double below = 0.0;
      for (int at = self, step = 0; at > 0; ++step) {
        const Entry& ea = at == self ? e : order_[static_cast<std::size_t>(at)];
        for (std::size_t k = 0; k < chain.size(); ++k) {
          if (ea.joint >= 0 && chain[k] == ea.joint) link.reach[k] = below;
        }
        below += at == self ? length : hop[static_cast<std::size_t>(at)];
        at = ea.parent;
      }
      e.link = static_cast<int>(links_.size());
      links_.push_back(std::move(link));
    }
    order_.push_back(e);
    chains.push_back(chain);
    for (const KDL::SegmentMap::const_iterator& child : GetTreeElementChildren(w.it->second)) {
      stack.push_back(Walk{child, self});
    }
  }
  scratch_.resize(order_.size());
}

KdlRobotModel::~KdlRobotModel() = default;

void KdlRobotModel::forward(const double* q, Eigen::Isometry3d* poses) const {
  scratch_[0] = Eigen::Isometry3d::Identity();
  for (std::size_t i = 1; i < order_.size(); ++i) {
    const Entry& e = order_[i];
    const double qi = e.joint >= 0 ? q[e.joint] : 0.0;
    scratch_[i] = scratch_[static_cast<std::size_t>(e.parent)] * toEigen(e.segment->pose(qi));
    if (e.link >= 0) poses[e.link] = scratch_[i];
  }
}

}  // namespace workspace_proximity
