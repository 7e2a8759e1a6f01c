#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_FILTER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_FILTER_H_

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/slam/particle_scan_matcher.h"
#include "robot_agent/slam/shared_grid_tiles.h"
#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"
#include "shared/core/thread_pool.h"

namespace fleetmap {

enum class ParticleProposal {
  kMotionModel,       // grid FastSLAM: sample odometry, weight by the scan likelihood
  kImprovedProposal,  // RBPF: sample a Gaussian fitted around the per-particle scan match
};

// Motion model noise (GMapping's srr, srt, str, stt): translation sigma = srr |dt| + srt |dr|,
// rotation sigma = str |dt| + stt |dr|, plus a floor.
struct MotionNoise {
  double srr = 0.0, srt = 0.0, str = 0.0, stt = 0.0;
  double min_translation_sigma = 0.0;
  double min_rotation_sigma = 0.0;

  // GMapping's defaults: wheel odometry over a metre is good to about 10 cm and 6 degrees.
  static MotionNoise WheelOdometry() { return {0.1, 0.2, 0.1, 0.2, 0.01, 0.005}; }
  // The scan-matching frontend's motion (ParticleSlamOptions::tracker): 5 mm and 0.06 deg per
  // metre, 3 mm and 0.06 deg at least. Its measured accuracy is finer still (the simulated
  // building lap, 427 m, ends 0.14-0.23 m off with 0.07 deg of heading error at worst), but on
  // intel a 2.5x tighter model read 0.019 m instead of 0.016 m and a 50x tighter one failed
  // (0.34 m); 2x looser let the building end 0.2-2.4 m off (docs/BENCHMARKS.md, issue 5,
  // session 12).
  static MotionNoise ScanMatched() { return {0.005, 0.0, 0.001, 0.0, 0.003, 0.001}; }
};

struct ParticleFilterOptions {
  int particles = 30;
  unsigned seed = 1;
  ParticleProposal proposal = ParticleProposal::kImprovedProposal;
  // Resample when N_eff < resample_threshold * N. A value above 1 resamples at every update.
  double resample_threshold = 0.5;
  MotionNoise motion_noise = MotionNoise::WheelOdometry();
  // Improved proposal: the Gaussian is fitted over a 3 x 3 x 3 lattice around the match.
  double lattice_step_translation = 0.025;
  double lattice_step_rotation = 0.01;
  // Where the lattice is centred. Off (GMapping): on the per-particle scan match, the mode of
  // the observation, which is where the product with a broad odometry prior peaks. On: on the
  // motion prediction, where the product peaks when the motion model is tighter than the
  // lattice (scan-matched motion). The match is then only the gate (share of points with a
  // correspondence at the prediction) and is not run. Why: at true poses on the simulated
  // building lap, the per-particle match against a particle's map of keyframes a metre apart is
  // off by +0.06 deg on average (0.13 deg RMS) per keyframe, a bias that its heading chains up
  // into 20+ m at the lap's end; the scan-matching frontend's motion is not (docs/BENCHMARKS.md,
  // issue 5, session 12).
  bool centre_on_prediction = false;
  // Scales the scan log-likelihood in the weights (GMapping's 1 / obsSigmaGain): a scan's ~100
  // points are not independent, and unscaled weights would collapse onto one particle.
  double observation_gain = 1.0 / 3.0;
  ParticleMatcherOptions matcher;
  // Along a direction the scan hardly observes (ParticleScan::normal_scatter eigenvalue below
  // this: a plain corridor's axis) the improved proposal's match keeps its start's translation.
  double min_observed_normals = 0.03;
  SharedTileGridOptions grid;
};

// One scan as the filter uses it: points for matching and weighting, rays for the map update
// (all in the robot frame).
struct ParticleScan {
  // Returns inside the horizon (see ParticleSlamOptions::match_range_margin): what the
  // improved proposal's scan match uses.
  std::vector<Eigen::Vector2f> match_points;
  // Every return: what the scan likelihood (the weights, the proposal's lattice) uses. The far
  // returns carry most of the heading information (with a fixed 1 m horizon margin applied to
  // the weights too, FastSLAM's ATE on the rectangle's 3 laps was ~2.5x worse over 4 seeds).
  std::vector<Eigen::Vector2f> weight_points;
  // NormalScatter of the matched returns: which directions the scan observes.
  Eigen::Matrix2d normal_scatter = Eigen::Matrix2d::Identity();
  Eigen::Vector2d sensor_origin = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> ray_ends;
  std::vector<uint8_t> ray_hits;
};

// Fills `out`'s rays (robot frame) from every beam with a positive finite range: to its return,
// or, past `max_range`, to max_range without a hit (it clears space but marks no wall). Beams
// without a return (glass, dropouts) are left out.
void SetRays(const LaserScan& scan, float max_range, ParticleScan* out);

// A particle's keyframe poses as a shared linked list: particles that descend from the same
// ancestor share the common part of their trajectories.
struct PoseNode {
  Rigid2d pose;
  int64_t index = 0;
  std::shared_ptr<const PoseNode> parent;
};

struct Particle {
  Rigid2d pose;
  double log_weight = 0.0;  // normalised over the particle set
  double score = 0.0;       // accumulated weight increments: picks the best particle
  SharedTileGrid map;
  std::shared_ptr<const PoseNode> history;
};

// The Rao-Blackwellized particle filter shared by grid FastSLAM and the improved-proposal RBPF:
// each particle carries a pose, a trajectory and a copy-on-write map. Per-particle work runs on
// `pool` (nullable); every particle draws from its own random stream, seeded from the seed, the
// update number and its index, so results depend on neither thread count nor scheduling.
class ParticleFilter {
 public:
  ParticleFilter(const ParticleFilterOptions& options, ThreadPool* pool);
  // Frees the pose histories iteratively (a recursive release of a long chain could overflow
  // the stack after many hours of driving).
  ~ParticleFilter();
  ParticleFilter(const ParticleFilter&) = delete;
  ParticleFilter& operator=(const ParticleFilter&) = delete;

  // First scan: every particle starts at `pose` with this scan in its map.
  void Initialize(const Rigid2d& pose, const ParticleScan& scan);
  // Moves every particle by `motion` (robot frame, from odometry or scan matching), weights it
  // by the scan, adds the scan to its map, and resamples when N_eff falls below the threshold.
  // `match_motion` is where the improved proposal starts its scan match (see DrawPose).
  void Update(const Rigid2d& motion, const Rigid2d& match_motion, const ParticleScan& scan);

  bool initialized() const { return !particles_.empty(); }
  const std::vector<Particle>& particles() const { return particles_; }
  int best_index() const;
  const Particle& best() const { return particles_[static_cast<size_t>(best_index())]; }
  // Keyframe poses of a particle, oldest first.
  std::vector<Rigid2d> History(int index) const;

  // N_eff of the weights after the latest update, before any resampling.
  double last_effective_sample_size() const { return last_neff_; }
  bool last_resampled() const { return last_resampled_; }
  int64_t updates() const { return updates_; }
  int64_t resamplings() const { return resamplings_; }
  int64_t proposal_fallbacks() const { return fallbacks_; }
  // Bytes of distinct map tiles over all particles, and what unshared grids would take.
  size_t UniqueTileBytes() const;
  size_t TotalTileBytes() const;

  // N_eff = 1 / sum w^2 of normalised (linear) weights.
  static double EffectiveSampleSize(const std::vector<double>& log_weights);

 private:
  void UpdateParticle(size_t index, const Rigid2d& motion, const Rigid2d& match_motion,
                      const ParticleScan& scan, bool* fallback);
  void InsertScan(Particle* particle, const ParticleScan& scan) const;
  void Resample();

  const ParticleFilterOptions options_;
  ThreadPool* pool_;
  std::vector<Particle> particles_;
  uint64_t next_owner_ = 1;
  double last_neff_ = 0.0;
  bool last_resampled_ = false;
  int64_t updates_ = 0;
  int64_t resamplings_ = 0;
  int64_t fallbacks_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_FILTER_H_
