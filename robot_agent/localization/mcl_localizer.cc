#include "robot_agent/localization/mcl_localizer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "shared/core/likelihood_field.h"

namespace fleetmap {
namespace {

bool Finite(const Rigid2d& pose) {
  return std::isfinite(pose.translation().x()) && std::isfinite(pose.translation().y()) &&
         std::isfinite(pose.rotation());
}

}  // namespace

MclLocalizer::MclLocalizer(const OccupancyGrid& map, const MclLocalizerOptions& options)
    : mcl_(FreeSpace::FromGrid(map), options.mcl),
      model_(LikelihoodField(map, LikelihoodFieldOptions()), options.laser),
      options_(options),
      gate_(options.density_interval, options.lost_density_interval) {
  if (options.initial_pose) {
    const double p = options.initial_position_std * options.initial_position_std;
    const double h = options.initial_heading_std * options.initial_heading_std;
    mcl_.InitializeGaussian(*options.initial_pose, Eigen::Vector3d(p, p, h).asDiagonal());
  } else {
    mcl_.InitializeUniform();
    if (options.seeding.enabled) seeder_ = std::make_unique<ScanSeeder>(map, options.seeding);
  }
  estimate_ = mcl_.Estimate();
}

void MclLocalizer::SeedFromScan(const LaserScan& scan) {
  if (!seeder_ || !mcl_.globally_localizing() ||
      scan.timestamp - last_seed_time_ < options_.seeding.interval) {
    return;
  }
  last_seed_time_ = scan.timestamp;
  const std::optional<CorrelativeMatch> match = seeder_->Search(ToPointsInRobotFrame(scan));
  if (!match) return;
  const Rigid2d& estimate = estimate_.robot_in_map;
  const bool agrees = estimate_.converged &&
                      (estimate.translation() - match->pose.translation()).norm() <=
                          options_.seeding.agreement_distance &&
                      std::abs(NormalizeAngle(estimate.rotation() - match->pose.rotation())) <=
                          options_.seeding.agreement_angle;
  if (agrees) {
    // The filter found the place the scan fits best: searching again costs and adds nothing.
    if (++seed_agreements_ >= options_.seeding.agreements_to_stop) seeder_.reset();
    return;
  }
  seed_agreements_ = 0;
  seeder_->Seed(match->pose, &mcl_.mutable_particles(), mcl_.rng());
  ++seeds_;
}

bool MclLocalizer::AddOdometry(const StampedPose& odometry, std::string* error) {
  if (!std::isfinite(odometry.timestamp) || !Finite(odometry.pose)) {
    *error = "odometry with a non-finite value";
    return false;
  }
  if (odometry.timestamp < last_input_time_) {
    *error = "odometry older than the previous input";
    return false;
  }
  last_input_time_ = odometry.timestamp;
  odometry_ = odometry;
  return true;
}

bool MclLocalizer::AddScan(const LaserScan& scan, std::string* error) {
  if (!std::isfinite(scan.timestamp)) {
    *error = "scan with a non-finite timestamp";
    return false;
  }
  if (scan.timestamp < last_input_time_) {
    *error = "scan older than the previous input";
    return false;
  }
  last_input_time_ = scan.timestamp;
  if (trajectory_.empty()) first_scan_time_ = scan.timestamp;
  if (odometry_ && !odometry_at_particles_) odometry_at_particles_ = odometry_->pose;
  const Rigid2d pending = PendingMotion();
  if (updates_ == 0 || pending.translation().norm() >= options_.update_min_translation ||
      std::abs(pending.rotation()) >= options_.update_min_rotation ||
      (options_.update_max_interval > 0.0 && !mcl_.globally_localizing() &&
       scan.timestamp - last_update_time_ >= options_.update_max_interval)) {
    last_update_time_ = scan.timestamp;
    FlushMotion();
    SeedFromScan(scan);
    mcl_.UpdateLaser(scan, model_);
    estimate_ = mcl_.Estimate();
    ++updates_;
    if (estimate_.converged && time_to_converge_ < 0.0) {
      time_to_converge_ = scan.timestamp - first_scan_time_;
    }
  }
  trajectory_.push_back({scan.timestamp, CurrentPose()});
  return true;
}

Rigid2d MclLocalizer::PendingMotion() const {
  if (!odometry_ || !odometry_at_particles_) return Rigid2d();
  return odometry_at_particles_->inverse() * odometry_->pose;
}

void MclLocalizer::FlushMotion() {
  if (!odometry_ || !odometry_at_particles_) return;
  const Rigid2d pending = PendingMotion();
  odometry_at_particles_ = odometry_->pose;
  if (pending.translation().isZero(0.0) && pending.rotation() == 0.0) return;
  mcl_.Predict(pending);
  estimate_ = mcl_.Estimate();
}

void MclLocalizer::SetMap(const OccupancyGrid& map) {
  mcl_.set_free_space(FreeSpace::FromGrid(map));
  if (seeder_) seeder_ = std::make_unique<ScanSeeder>(map, options_.seeding);
  model_ = LikelihoodFieldModel(LikelihoodField(map, LikelihoodFieldOptions()), options_.laser);
}

Rigid2d MclLocalizer::CurrentPose() const { return estimate_.robot_in_map * PendingMotion(); }

std::optional<PoseDensity> MclLocalizer::DensityOfSeenRobot(const RobotDetection& detection) {
  FlushMotion();  // the particles where the robot is now
  std::optional<PoseDensity> density =
      SummarizeDetection(mcl_.particles(), detection, options_.summary, mcl_.rng());
  if (density) ++densities_sent_;
  return density;
}

bool MclLocalizer::ApplyDensity(const PoseDensity& density) {
  if (!(std::abs(density.timestamp - last_input_time_) <= options_.max_density_age)) {
    ++densities_stale_;
    return false;
  }
  FlushMotion();
  if (!gate_.Allow(density.observer_id, density.observed_id, density.timestamp,
                   mcl_.globally_localizing())) {
    ++densities_skipped_;
    return false;
  }
  if (!ApplyPoseDensity(density, options_.density, &mcl_)) {
    ++densities_refused_;
    return false;
  }
  ++densities_applied_;
  estimate_ = mcl_.Estimate();
  // Another robot said where this one is. The search cannot tell look-alike places apart (in a
  // symmetric building it prefers one twin), so it must not pull the belief back to its choice.
  seeder_.reset();
  return true;
}

std::string MclLocalizer::Statistics() const {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << "MCL: " << trajectory_.size() << " scans (" << updates_ << " laser corrections), "
      << (estimate_.converged ? "converged" : "not converged") << " (position std "
      << MaxPositionStd(estimate_.covariance) << " m, heading std "
      << std::sqrt(std::max(0.0, estimate_.covariance(2, 2))) << " rad, "
      << estimate_.particle_count << " particles)";
  if (time_to_converge_ >= 0.0) out << ", first converged after " << time_to_converge_ << " s";
  if (seeds_ > 0 || seeder_) {
    out << "; scan-to-map seeds " << seeds_ << (seeder_ ? " (still searching)" : "");
  }
  out << "; densities of robots it saw: " << densities_sent_ << "; densities from others: applied "
      << densities_applied_ << ", refused " << densities_refused_ << ", too soon "
      << densities_skipped_ << ", stale " << densities_stale_;
  return out.str();
}

}  // namespace fleetmap
