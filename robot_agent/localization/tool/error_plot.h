#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_ERROR_PLOT_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_ERROR_PLOT_H_

#include <string>
#include <utility>
#include <vector>

namespace fleetmap {

// One line of the plot: (time s, error m) points in time order.
struct ErrorSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;
};

struct ErrorPlotOptions {
  int width = 900;
  int height = 420;
  double max_error = 2.0;  // metres at the top edge; larger errors are clipped
};

// Draws error-vs-time lines (one colour per series, in the order of kPlotColourNames) over grey
// grid lines every `TickStep` and writes an RGB PNG. There is no text: the tool prints the
// scale and the legend. Returns false with `error` filled when the file cannot be written.
bool WriteErrorPlot(const std::string& path, const std::vector<ErrorSeries>& series,
                    const ErrorPlotOptions& options, std::string* error);

// Names of the colours used, in order (for the printed legend).
extern const char* const kPlotColourNames[6];

// A round grid step (1, 2 or 5 times a power of ten) giving about `ticks` lines over `range`.
double TickStep(double range, int ticks);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_ERROR_PLOT_H_
