#ifndef FLEETMAP_SHARED_EVAL_STATISTICS_H_
#define FLEETMAP_SHARED_EVAL_STATISTICS_H_

#include <vector>

namespace fleetmap {

// Mean and population standard deviation (divides by n, as the Kümmerle et al. 2009
// evaluation tool does), plus the extremes. All zero for no values.
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
  double max = 0.0;
  int count = 0;
};

MeanStd ComputeMeanStd(const std::vector<double>& values);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_STATISTICS_H_
