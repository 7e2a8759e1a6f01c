#include "robot_agent/slam/particle_proposal.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <vector>

#include "shared/matching/degeneracy.h"

namespace fleetmap {
namespace {

uint64_t SplitMix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

void MotionSigmas(const Rigid2d& motion, const ParticleFilterOptions& options, double* sigma_t,
                  double* sigma_r) {
  const MotionNoise& o = options.motion_noise;
  const double dt = motion.translation().norm(), dr = std::abs(motion.rotation());
  *sigma_t = o.srr * dt + o.srt * dr + o.min_translation_sigma;
  *sigma_r = o.str * dt + o.stt * dr + o.min_rotation_sigma;
}

double Gaussian(std::mt19937_64* rng) {
  // Box-Muller on raw 53-bit uniforms: identical on every standard library, unlike
  // std::normal_distribution.
  const double u1 = (static_cast<double>((*rng)() >> 11) + 1.0) * (1.0 / 9007199254740993.0);
  const double u2 = static_cast<double>((*rng)() >> 11) * (1.0 / 9007199254740992.0);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

std::mt19937_64 ParticleRandomStream(unsigned seed, int64_t update, size_t index) {
  return std::mt19937_64(SplitMix(SplitMix(SplitMix(seed) ^ static_cast<uint64_t>(update)) ^ index));
}

Rigid2d SampleMotion(const Rigid2d& pose, const Rigid2d& motion, const ParticleFilterOptions& options,
                     std::mt19937_64* rng) {
  double sigma_t, sigma_r;
  MotionSigmas(motion, options, &sigma_t, &sigma_r);
  const Rigid2d noise(sigma_t * Gaussian(rng), sigma_t * Gaussian(rng), sigma_r * Gaussian(rng));
  return pose * motion * noise;
}

double MotionLogDensity(const Rigid2d& pose, const Rigid2d& motion, const Rigid2d& candidate,
                        const ParticleFilterOptions& options) {
  double sigma_t, sigma_r;
  MotionSigmas(motion, options, &sigma_t, &sigma_r);
  const Rigid2d error = (pose * motion).inverse() * candidate;
  const double r = NormalizeAngle(error.rotation());
  return -0.5 * (error.translation().squaredNorm() / (sigma_t * sigma_t) + r * r / (sigma_r * sigma_r));
}

ProposalDraw DrawPose(const Rigid2d& pose, const Rigid2d& motion, const Rigid2d& match_motion,
                      const ParticleScan& scan,
                      const SharedTileGrid& map, const ParticleFilterOptions& options,
                      std::mt19937_64* rng) {
  const double gain = options.observation_gain;
  // Along a direction the scan does not observe (a plain corridor's axis) neither the match nor
  // the weights can correct a pose, so neither a match sliding along it nor sampled noise is
  // kept there: the pose keeps `start`'s translation along it.
  auto keep_observed = [&](const Rigid2d& start, const Rigid2d& candidate) {
    if (options.min_observed_normals <= 0.0) return candidate;
    return KeepObservedDirections(start, candidate, scan.normal_scatter,
                                  options.min_observed_normals);
  };
  ProposalDraw draw;
  if (options.proposal == ParticleProposal::kImprovedProposal) {
    const Rigid2d start = pose * match_motion;
    ParticleMatch match;
    if (options.centre_on_prediction) {
      match.pose = pose * motion;
      match.good = GoodMatchAt(scan.match_points, map, match.pose, options.matcher);
    } else {
      match = MatchAgainstTiles(scan.match_points, map, start, options.matcher);
    }
    if (match.good) match.pose = keep_observed(start, match.pose);
    if (match.good) {
      // Lattice around the mode; offsets in the mode's frame keep angles away from the wrap.
      std::vector<Eigen::Vector3d> offsets;
      std::vector<double> log_w;
      double max_log_w = -1e300;
      for (int i = -1; i <= 1; ++i) {
        for (int j = -1; j <= 1; ++j) {
          for (int k = -1; k <= 1; ++k) {
            const Eigen::Vector3d offset(i * options.lattice_step_translation,
                                         j * options.lattice_step_translation,
                                         k * options.lattice_step_rotation);
            const Rigid2d candidate = match.pose * Rigid2d(offset.x(), offset.y(), offset.z());
            const double w =
                gain * ScanLogLikelihood(scan.weight_points, map, candidate, options.matcher) +
                MotionLogDensity(pose, motion, candidate, options);
            offsets.push_back(offset);
            log_w.push_back(w);
            max_log_w = std::max(max_log_w, w);
          }
        }
      }
      double eta = 0.0;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (size_t n = 0; n < offsets.size(); ++n) {
        const double w = std::exp(log_w[n] - max_log_w);
        eta += w;
        mean += w * offsets[n];
      }
      mean /= eta;
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (size_t n = 0; n < offsets.size(); ++n) {
        const Eigen::Vector3d d = offsets[n] - mean;
        covariance += std::exp(log_w[n] - max_log_w) / eta * d * d.transpose();
      }
      // A floor keeps the Cholesky factor defined when one lattice point takes all the weight.
      covariance += Eigen::Vector3d(1e-8, 1e-8, 1e-9).asDiagonal();
      const Eigen::Matrix3d lower = covariance.llt().matrixL();
      const Eigen::Vector3d z(Gaussian(rng), Gaussian(rng), Gaussian(rng));
      const Eigen::Vector3d sample = mean + lower * z;
      draw.pose = keep_observed(start, match.pose * Rigid2d(sample.x(), sample.y(), sample.z()));
      draw.log_weight_increment = max_log_w + std::log(eta);
      draw.used_scan_match = true;
      return draw;
    }
  }
  draw.pose = keep_observed(pose * motion, SampleMotion(pose, motion, options, rng));
  draw.log_weight_increment =
      gain * ScanLogLikelihood(scan.weight_points, map, draw.pose, options.matcher);
  return draw;
}

}  // namespace fleetmap
