#include "robot_agent/slam/particle_loop_closure.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace fleetmap {
namespace {

// A settled keyframe the filter later moved by more than this counts as revised.
constexpr double kRevisionTranslation = 0.01;
constexpr double kRevisionRotation = 0.002;

// Whether a pose moved by more than what rounding could explain.
bool Differ(const Rigid2d& a, const Rigid2d& b) {
  const Rigid2d delta = a.inverse() * b;
  return delta.translation().norm() > 1e-5 || std::abs(delta.rotation()) > 1e-6;
}

}  // namespace

int64_t NewestSharedKeyframe(const std::vector<Particle>& particles, int64_t from) {
  if (particles.empty() || !particles.front().history) return -1;
  // Each particle's nodes at index >= from, newest first; histories have equal lengths.
  auto nodes_from = [from](const Particle& particle) {
    std::vector<const PoseNode*> nodes;
    for (const PoseNode* node = particle.history.get(); node != nullptr && node->index >= from;
         node = node->parent.get()) {
      nodes.push_back(node);
    }
    return nodes;
  };
  const std::vector<const PoseNode*> first = nodes_from(particles.front());
  std::vector<std::vector<const PoseNode*>> others;
  for (size_t p = 1; p < particles.size(); ++p) others.push_back(nodes_from(particles[p]));
  for (size_t i = 0; i < first.size(); ++i) {
    const bool shared = std::all_of(others.begin(), others.end(), [&](const auto& nodes) {
      return i < nodes.size() && nodes[i] == first[i];
    });
    if (shared) return first[i]->index;  // the ancestors of a shared node are shared too
  }
  return -1;
}

ParticleLoopClosure::ParticleLoopClosure(const ParticleLoopClosureOptions& options,
                                         int keyframes_per_submap)
    : options_(options),
      per_submap_(static_cast<size_t>(std::max(1, keyframes_per_submap))),
      closure_(std::make_unique<LoopClosure>(options.graph)) {}

void ParticleLoopClosure::AddScan(double timestamp, size_t keyframe, const Rigid2d& offset,
                                  std::vector<Eigen::Vector2f> points) {
  if (points.empty() || keyframe < settled_.size()) return;
  pending_.push_back({timestamp, keyframe, offset, std::move(points)});
}

bool ParticleLoopClosure::Update(const std::vector<Rigid2d>& filter_poses, int64_t shared_up_to) {
  CountRevisions(filter_poses);
  corrections_changed_ = false;
  const size_t newest = filter_poses.empty() ? 0 : filter_poses.size() - 1;
  const size_t by_age = filter_poses.size() > static_cast<size_t>(options_.settle_keyframes)
                            ? filter_poses.size() - static_cast<size_t>(options_.settle_keyframes)
                            : 0;  // keyframes [0, by_age) are old enough
  while (settled_.size() < newest &&
         (settled_.size() < by_age || static_cast<int64_t>(settled_.size()) <= shared_up_to)) {
    if (static_cast<int64_t>(settled_.size()) <= shared_up_to) ++settled_shared_;
    Settle(settled_.size(), filter_poses);
  }
  submaps_moved_ = submaps_moved_ || corrections_changed_;
  worst_lag_ = std::max(worst_lag_, filter_poses.size() - settled_.size());
  return corrections_changed_;
}

bool ParticleLoopClosure::Finish(const std::vector<Rigid2d>& filter_poses) {
  CountRevisions(filter_poses);
  corrections_changed_ = false;
  if (options_.rebuild_at_finish && revised_count_ > 0) {
    Restart();
    corrections_changed_ = true;
  }
  while (settled_.size() < filter_poses.size()) Settle(settled_.size(), filter_poses);
  if (closure_->Finish()) corrections_changed_ = true;
  submaps_moved_ = submaps_moved_ || corrections_changed_;
  return corrections_changed_;
}

void ParticleLoopClosure::Settle(size_t keyframe, const std::vector<Rigid2d>& filter_poses) {
  // Chained by the filter's relative pose, so that the layer's chain stays continuous even when
  // the filter moved an already settled keyframe.
  settled_.push_back(LocalKeyframePose(keyframe, filter_poses));
  filter_at_settle_.push_back(filter_poses[keyframe]);
  revised_.push_back(false);
  const size_t group = keyframe / per_submap_;
  const Rigid2d submap_in_local(settled_[group * per_submap_].translation(), 0.0);
  while (!pending_.empty() && pending_.front().keyframe <= keyframe) {
    const PendingScan& scan = pending_.front();
    const Rigid2d local = settled_[scan.keyframe] * scan.offset;
    bool node = !last_node_ || scan.offset.translation().norm() < 1e-9;  // keyframe scans
    if (last_node_) {
      const Rigid2d moved = last_node_->inverse() * local;
      node = node || moved.translation().norm() >= options_.node_min_translation ||
             std::abs(moved.rotation()) >= options_.node_min_rotation;
    }
    if (node) {
      // Nodes of one keyframe group share its submap id and its anchor, as ParticleSubmaps
      // renders it (the group's first keyframe, map axes).
      if (closure_->AddNode(scan.timestamp, scan.points, local, static_cast<int64_t>(group),
                            submap_in_local)) {
        corrections_changed_ = true;
      }
      last_node_ = local;
      if (options_.rebuild_at_finish) nodes_.push_back(std::move(pending_.front()));
    }
    pending_.pop_front();
  }
}

void ParticleLoopClosure::Restart() {
  closure_ = std::make_unique<LoopClosure>(options_.graph);
  for (auto scan = nodes_.rbegin(); scan != nodes_.rend(); ++scan) {
    pending_.push_front(std::move(*scan));
  }
  nodes_.clear();
  settled_.clear();
  filter_at_settle_.clear();
  revised_.clear();
  last_node_.reset();
  rebuilt_ = true;
}

Rigid2d ParticleLoopClosure::LocalKeyframePose(size_t keyframe,
                                               const std::vector<Rigid2d>& filter_poses) const {
  if (keyframe < settled_.size()) return settled_[keyframe];
  if (settled_.empty()) return filter_poses[keyframe];
  const size_t last = settled_.size() - 1;
  return settled_[last] * (filter_poses[last].inverse() * filter_poses[keyframe]);
}

std::vector<Rigid2d> ParticleLoopClosure::LocalKeyframePoses(
    const std::vector<Rigid2d>& filter_poses) const {
  std::vector<Rigid2d> poses;
  poses.reserve(filter_poses.size());
  for (size_t k = 0; k < filter_poses.size(); ++k)
    poses.push_back(LocalKeyframePose(k, filter_poses));
  return poses;
}

void ParticleLoopClosure::CountRevisions(const std::vector<Rigid2d>& filter_poses) {
  for (size_t k = 0; k < filter_at_settle_.size() && k < filter_poses.size(); ++k) {
    const Rigid2d delta = filter_at_settle_[k].inverse() * filter_poses[k];
    const double moved = delta.translation().norm();
    if (moved <= kRevisionTranslation && std::abs(delta.rotation()) <= kRevisionRotation) continue;
    worst_revision_ = std::max(worst_revision_, moved);
    if (!revised_[k]) {
      revised_[k] = true;
      ++revised_count_;
    }
  }
}

ParticleLoopClosure::Placement ParticleLoopClosure::ToCorrected(int64_t submap_id,
                                                                const Placement& local) const {
  Placement corrected = local;
  const std::optional<Rigid2d> anchor = closure_->SubmapInGlobal(submap_id);
  const double start = local.scan_poses.empty() ? 0.0 : local.scan_poses.front().timestamp;
  corrected.submap_in_local = anchor ? *anchor : Corrected(start, local.submap_in_local);
  for (StampedPose& scan : corrected.scan_poses) scan.pose = Corrected(scan.timestamp, scan.pose);
  return corrected;
}

void ParticleLoopClosure::CorrectSubmap(Submap* submap) {
  Published& published = published_[submap->submap_id];
  published.local = {submap->submap_in_local, submap->scan_poses};
  published.corrected = ToCorrected(submap->submap_id, published.local);
  submap->submap_in_local = published.corrected.submap_in_local;
  submap->scan_poses = published.corrected.scan_poses;
  submap->revision = ++published.revision;
}

bool ParticleLoopClosure::Moved(const Placement& before, const Placement& after) {
  if (Differ(before.submap_in_local, after.submap_in_local)) return true;
  for (size_t i = 0; i < before.scan_poses.size() && i < after.scan_poses.size(); ++i) {
    if (Differ(before.scan_poses[i].pose, after.scan_poses[i].pose)) return true;
  }
  return false;
}

std::vector<int64_t> ParticleLoopClosure::TakeMovedSubmaps() {
  std::vector<int64_t> moved;
  if (!submaps_moved_) return moved;
  submaps_moved_ = false;
  for (const auto& [id, published] : published_) {
    if (Moved(published.corrected, ToCorrected(id, published.local))) moved.push_back(id);
  }
  return moved;
}

std::string ParticleLoopClosure::Statistics() const {
  std::ostringstream out;
  out << "loop closure: " << settled_.size() << " keyframes settled (" << settled_shared_
      << " shared by every particle), " << revised_count_ << " later moved by the filter (worst "
      << worst_revision_ << " m), at most " << worst_lag_ << " keyframes unsettled"
      << (rebuilt_ ? ", graph rebuilt at the end; " : "; ") << closure_->nodes() << " nodes, "
      << closure_->searches() << " searches, " << closure_->loop_constraints() << " constraints, "
      << closure_->optimizations() << " optimisations";
  return out.str();
}

}  // namespace fleetmap
