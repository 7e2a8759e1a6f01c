#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_PROPOSAL_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_PROPOSAL_H_

#include <random>

#include "robot_agent/slam/particle_filter.h"

namespace fleetmap {

// The random stream of particle `index` at update `update`: a pure function of the seed, so
// results do not depend on which thread draws.
std::mt19937_64 ParticleRandomStream(unsigned seed, int64_t update, size_t index);

// Odometry motion model: `pose` moved by `motion` with Gaussian noise in the robot frame.
Rigid2d SampleMotion(const Rigid2d& pose, const Rigid2d& motion, const ParticleFilterOptions& options,
                     std::mt19937_64* rng);
// Log density (up to a constant) of `candidate` under the motion model from `pose`.
double MotionLogDensity(const Rigid2d& pose, const Rigid2d& motion, const Rigid2d& candidate,
                        const ParticleFilterOptions& options);

struct ProposalDraw {
  Rigid2d pose;
  double log_weight_increment = 0.0;
  bool used_scan_match = false;
};

// One particle's step. Improved proposal (Grisetti et al. 2007): scan match from the odometry
// prediction; when good, fit a Gaussian to odometry x observation likelihood over a lattice
// around the match, draw from it and weight by its normaliser. Otherwise (or for FastSLAM):
// draw from the motion model and weight by the scan likelihood. The match starts from
// `pose * match_motion` (the per-scan tracked motion: a far better start than raw odometry
// after a metre of travel); the proposal itself weighs candidates by the odometry `motion`.
ProposalDraw DrawPose(const Rigid2d& pose, const Rigid2d& motion, const Rigid2d& match_motion,
                      const ParticleScan& scan,
                      const SharedTileGrid& map, const ParticleFilterOptions& options,
                      std::mt19937_64* rng);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_PROPOSAL_H_
