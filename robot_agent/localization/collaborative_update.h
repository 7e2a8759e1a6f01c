#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_COLLABORATIVE_UPDATE_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_COLLABORATIVE_UPDATE_H_

#include <map>
#include <string>
#include <utility>

#include "robot_agent/localization/mcl.h"
#include "robot_agent/localization/pose_density.h"

namespace fleetmap {

struct DensityUpdateOptions {
  // The detection may be wrong (a misidentified robot): its density is mixed with this much of
  // a uniform density over the free space, so a contradicting detection cannot empty the belief.
  double outlier_probability = 0.05;
  // New particles drawn from the detection density (a mixture proposal), as a fraction of the
  // filter's maximum particle count (KLD max_particles). Without
  // them a lost robot, whose few thousand particles are spread over the whole building, would
  // rarely have a particle inside the detection's few square centimetres.
  double injection_fraction = 0.3;
  // The belief may be wrong too (a lost robot that settled in the wrong one of two look-alike
  // corridors): it is mixed with this much of a uniform density before the product. Smaller
  // than outlier_probability, so that a focused robot trusts itself over a contradicting
  // detection (5:1 by default) but still keeps a few particles where the detection says it is.
  double belief_floor_probability = 0.01;
  // The same while the observed robot is still globally localizing (Mcl::globally_localizing()):
  // after a uniform start its belief may have converged on a look-alike place (a corridor seen
  // from behind looks the same 30 m further on), and particle depletion leaves no particles at
  // the true pose. With the small floor the detection, whose heading is unknown, would lose
  // to the wrong but confident belief until several detections had accumulated.
  // Only for a density that pins the robot down: kernel centres spread by at most this much
  // (metres). A vague one from a barely focused observer must not wipe out the belief.
  double lost_belief_floor_probability = 0.5;
  double lost_floor_max_spread = 0.3;
  // A detection confirms a globally localizing belief (and clears the flag) when the old
  // particles carry more than this share of the updated weight by agreeing with it, i.e. the
  // belief already agreed with the detection, and the estimate after the update lies within
  // confirmation_distance (metres) of where the detection puts the robot. A belief that
  // disagreed stays suspect for the next detection.
  double confirmation_share = 0.5;
  double confirmation_distance = 0.5;
};

// Observed side of eq. 15: multiplies the belief of `mcl` by `density` and resamples. Uses a
// mixture proposal: the old particles weighted by the density, plus samples from the density
// weighted by a kernel estimate of the old belief. Returns false (belief unchanged) when the
// density or the belief is empty. Clears mcl->globally_localizing() when the detection
// confirms the belief (see confirmation_share).
bool ApplyPoseDensity(const PoseDensity& density, const DensityUpdateOptions& options, Mcl* mcl);

// Rate limit against double counting: the same pair (observer, observed) may feed one update per
// `min_interval` seconds, since consecutive detections of a pair share almost all their
// information (the same two beliefs). Pure bookkeeping; the caller passes the times.
//
// An observed robot still globally localizing (Mcl::globally_localizing()) may take one per
// `lost_min_interval` instead: a detection without a relative heading leaves its belief at the
// right place with every heading, and in a corridor the laser cannot tell a heading from its
// opposite; the next detection, a moment later, finds the robot where it drove, which the
// particles headed the wrong way did not (half a second at walking pace puts them half a metre
// off). With 2 s, 6 of 150 simulated lost robots waited 2-4 s for it (docs/BENCHMARKS.md, issue
// 10). Once a detection confirms its belief, the robot is no longer globally localizing and
// min_interval holds again.
class DetectionGate {
 public:
  explicit DetectionGate(double min_interval = 2.0, double lost_min_interval = 0.5)
      : min_interval_(min_interval), lost_min_interval_(lost_min_interval) {}
  // True (and records the use) when the pair may be used at `timestamp`; `observed_lost`: the
  // observed robot is globally localizing.
  bool Allow(const std::string& observer_id, const std::string& observed_id, double timestamp,
             bool observed_lost = false);

 private:
  double min_interval_;
  double lost_min_interval_;
  std::map<std::pair<std::string, std::string>, double> last_use_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_COLLABORATIVE_UPDATE_H_
