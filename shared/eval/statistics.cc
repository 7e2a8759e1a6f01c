#include "shared/eval/statistics.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd result;
  if (values.empty()) return result;
  result.count = static_cast<int>(values.size());
  double sum = 0.0;
  result.max = values.front();
  for (double v : values) {
    sum += v;
    result.max = std::max(result.max, v);
  }
  result.mean = sum / result.count;
  double squares = 0.0;
  for (double v : values) squares += (v - result.mean) * (v - result.mean);
  result.std = std::sqrt(squares / result.count);
  return result;
}

}  // namespace fleetmap
