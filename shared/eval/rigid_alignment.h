#ifndef FLEETMAP_SHARED_EVAL_RIGID_ALIGNMENT_H_
#define FLEETMAP_SHARED_EVAL_RIGID_ALIGNMENT_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// The rigid transform T minimising sum |target_i - T * source_i|^2 (closed form, Horn/Umeyama
// without scale, in 2D). Needs at least two distinct source points of equal count to the
// targets; otherwise there is no unique answer and nullopt is returned.
std::optional<Rigid2d> AlignPoints2d(const std::vector<Eigen::Vector2d>& source,
                                     const std::vector<Eigen::Vector2d>& target);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_RIGID_ALIGNMENT_H_
