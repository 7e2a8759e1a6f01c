#include "robot_agent/slam/particle_filter.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "robot_agent/slam/particle_proposal.h"

namespace fleetmap {

ParticleFilter::ParticleFilter(const ParticleFilterOptions& options, ThreadPool* pool)
    : options_(options), pool_(pool) {}

ParticleFilter::~ParticleFilter() {
  for (Particle& particle : particles_) {
    std::shared_ptr<const PoseNode> node = std::move(particle.history);
    while (node && node.use_count() == 1) {
      std::shared_ptr<const PoseNode> parent = node->parent;
      node = std::move(parent);  // frees the old node; its parent survives in `node`
    }
  }
}

void SetRays(const LaserScan& scan, float max_range, ParticleScan* out) {
  out->sensor_origin = scan.sensor_in_robot.translation();
  out->ray_ends.clear();
  out->ray_hits.clear();
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const float range = scan.ranges[i];
    if (!std::isfinite(range) || range <= 0.0f) continue;
    const bool hit = range <= max_range;
    const double r = hit ? range : max_range;
    const double angle = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    out->ray_ends.push_back(scan.sensor_in_robot * Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle)));
    out->ray_hits.push_back(hit ? 1 : 0);
  }
}

void ParticleFilter::InsertScan(Particle* particle, const ParticleScan& scan) const {
  std::vector<Eigen::Vector2d> ends;
  ends.reserve(scan.ray_ends.size());
  for (const Eigen::Vector2d& end : scan.ray_ends) ends.push_back(particle->pose * end);
  particle->map.InsertRays(particle->pose * scan.sensor_origin, ends, scan.ray_hits);
}

void ParticleFilter::Initialize(const Rigid2d& pose, const ParticleScan& scan) {
  const int n = std::max(1, options_.particles);
  Particle first{pose, 0.0, 0.0, SharedTileGrid(options_.grid, next_owner_++), nullptr};
  InsertScan(&first, scan);
  first.history = std::make_shared<const PoseNode>(PoseNode{pose, 0, nullptr});
  first.log_weight = -std::log(static_cast<double>(n));
  particles_.assign(static_cast<size_t>(n), first);
  // Every copy shares the first map; none may write to it in place.
  for (Particle& particle : particles_) particle.map.set_owner(next_owner_++);
  last_neff_ = n;
}

void ParticleFilter::UpdateParticle(size_t index, const Rigid2d& motion, const Rigid2d& match_motion,
                                    const ParticleScan& scan, bool* fallback) {
  Particle& particle = particles_[index];
  std::mt19937_64 rng = ParticleRandomStream(options_.seed, updates_, index);
  const ProposalDraw draw = DrawPose(particle.pose, motion, match_motion, scan, particle.map, options_, &rng);
  *fallback = options_.proposal == ParticleProposal::kImprovedProposal && !draw.used_scan_match;
  particle.pose = draw.pose;
  particle.log_weight += draw.log_weight_increment;
  particle.score += draw.log_weight_increment;
  InsertScan(&particle, scan);
  particle.history = std::make_shared<const PoseNode>(
      PoseNode{particle.pose, particle.history ? particle.history->index + 1 : 0, particle.history});
}

void ParticleFilter::Update(const Rigid2d& motion, const Rigid2d& match_motion, const ParticleScan& scan) {
  if (!initialized()) {
    Initialize(motion, scan);
    return;
  }
  ++updates_;
  std::vector<char> fallbacks(particles_.size(), 0);
  auto body = [&](size_t i) {
    bool fallback = false;
    UpdateParticle(i, motion, match_motion, scan, &fallback);
    fallbacks[i] = fallback;
  };
  if (pool_ != nullptr) {
    pool_->ParallelFor(particles_.size(), body);
  } else {
    for (size_t i = 0; i < particles_.size(); ++i) body(i);
  }
  for (char f : fallbacks) fallbacks_ += f;

  // Normalise in the log domain.
  double max_w = -1e300;
  for (const Particle& p : particles_) max_w = std::max(max_w, p.log_weight);
  double sum = 0.0;
  for (const Particle& p : particles_) sum += std::exp(p.log_weight - max_w);
  const double log_sum = max_w + std::log(sum);
  std::vector<double> log_weights;
  for (Particle& p : particles_) {
    p.log_weight -= log_sum;
    log_weights.push_back(p.log_weight);
  }
  last_neff_ = EffectiveSampleSize(log_weights);
  last_resampled_ = last_neff_ < options_.resample_threshold * static_cast<double>(particles_.size());
  if (last_resampled_) Resample();
}

double ParticleFilter::EffectiveSampleSize(const std::vector<double>& log_weights) {
  if (log_weights.empty()) return 0.0;
  double max_w = -1e300;
  for (double w : log_weights) max_w = std::max(max_w, w);
  double sum = 0.0, sum_sq = 0.0;
  for (double w : log_weights) {
    const double e = std::exp(w - max_w);
    sum += e;
    sum_sq += e * e;
  }
  return sum * sum / sum_sq;
}

// Systematic (low-variance) resampling with one uniform draw from the update's own stream.
void ParticleFilter::Resample() {
  ++resamplings_;
  const size_t n = particles_.size();
  std::mt19937_64 rng = ParticleRandomStream(options_.seed, updates_, n);
  const double start = static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0) / static_cast<double>(n);
  std::vector<Particle> resampled;
  resampled.reserve(n);
  double cumulative = std::exp(particles_[0].log_weight);
  size_t source = 0;
  for (size_t i = 0; i < n; ++i) {
    const double target = start + static_cast<double>(i) / static_cast<double>(n);
    while (target > cumulative && source + 1 < n) cumulative += std::exp(particles_[++source].log_weight);
    resampled.push_back(particles_[source]);
  }
  const double uniform = -std::log(static_cast<double>(n));
  for (Particle& p : resampled) {
    p.log_weight = uniform;
    // Copies share all tiles: from now on every particle clones before it writes.
    p.map.set_owner(next_owner_++);
  }
  particles_ = std::move(resampled);
}

int ParticleFilter::best_index() const {
  int best = 0;
  for (size_t i = 1; i < particles_.size(); ++i) {
    if (particles_[i].score > particles_[static_cast<size_t>(best)].score) best = static_cast<int>(i);
  }
  return best;
}

std::vector<Rigid2d> ParticleFilter::History(int index) const {
  std::vector<Rigid2d> poses;
  if (index < 0 || static_cast<size_t>(index) >= particles_.size()) return poses;
  for (const PoseNode* node = particles_[static_cast<size_t>(index)].history.get(); node != nullptr;
       node = node->parent.get()) {
    poses.push_back(node->pose);
  }
  std::reverse(poses.begin(), poses.end());
  return poses;
}

size_t ParticleFilter::UniqueTileBytes() const {
  std::unordered_set<const SharedTileGrid::Tile*> tiles;
  for (const Particle& p : particles_) p.map.CollectTiles(&tiles);
  return tiles.size() * SharedTileGrid::TileBytes();
}

size_t ParticleFilter::TotalTileBytes() const {
  size_t n = 0;
  for (const Particle& p : particles_) n += p.map.tile_count();
  return n * SharedTileGrid::TileBytes();
}

}  // namespace fleetmap
