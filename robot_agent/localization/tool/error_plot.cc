#include "robot_agent/localization/tool/error_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "shared/io/map_file.h"

namespace fleetmap {

const char* const kPlotColourNames[6] = {"red", "blue", "green", "orange", "purple", "cyan"};

namespace {

constexpr uint8_t kColours[6][3] = {{220, 30, 30}, {30, 60, 220}, {20, 160, 40},
                                    {240, 140, 0}, {150, 40, 180}, {0, 180, 200}};

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height), pixels_(size_t(width) * height * 3, 255) {}
  void Set(int x, int y, const uint8_t* rgb) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    uint8_t* p = &pixels_[(static_cast<size_t>(y) * width_ + x) * 3];
    p[0] = rgb[0];
    p[1] = rgb[1];
    p[2] = rgb[2];
  }
  // Bresenham line, drawn `thickness` pixels tall.
  void Line(int x0, int y0, int x1, int y1, const uint8_t* rgb, int thickness = 1) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    while (true) {
      for (int t = 0; t < thickness; ++t) Set(x0, y0 + t, rgb);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) {
        err += dy;
        x0 += sx;
      }
      if (e2 <= dx) {
        err += dx;
        y0 += sy;
      }
    }
  }
  const std::vector<uint8_t>& pixels() const { return pixels_; }

 private:
  int width_;
  int height_;
  std::vector<uint8_t> pixels_;
};

}  // namespace

double TickStep(double range, int ticks) {
  if (!(range > 0.0) || ticks <= 0) return 1.0;
  const double raw = range / ticks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

bool WriteErrorPlot(const std::string& path, const std::vector<ErrorSeries>& series,
                    const ErrorPlotOptions& options, std::string* error) {
  const int w = std::max(options.width, 100), h = std::max(options.height, 80);
  const int margin = 30;
  Canvas canvas(w, h);
  double max_time = 1.0;
  for (const ErrorSeries& s : series) {
    for (const auto& [t, e] : s.points) max_time = std::max(max_time, t);
  }
  const double max_error = options.max_error > 0.0 ? options.max_error : 1.0;
  const auto to_x = [&](double t) {
    return margin + static_cast<int>(std::lround(t / max_time * (w - 2 * margin)));
  };
  const auto to_y = [&](double e) {
    return h - margin -
           static_cast<int>(std::lround(std::min(e, max_error) / max_error * (h - 2 * margin)));
  };
  const uint8_t grey[3] = {210, 210, 210}, black[3] = {0, 0, 0};
  const double time_step = TickStep(max_time, 10), error_step = TickStep(max_error, 8);
  for (double t = 0.0; t <= max_time + 1e-9; t += time_step) {
    canvas.Line(to_x(t), to_y(0), to_x(t), to_y(max_error), grey);
  }
  for (double e = 0.0; e <= max_error + 1e-9; e += error_step) {
    canvas.Line(to_x(0), to_y(e), to_x(max_time), to_y(e), grey);
  }
  canvas.Line(to_x(0), to_y(0), to_x(max_time), to_y(0), black);
  canvas.Line(to_x(0), to_y(0), to_x(0), to_y(max_error), black);
  for (size_t i = 0; i < series.size(); ++i) {
    const uint8_t* colour = kColours[i % 6];
    const auto& points = series[i].points;
    for (size_t k = 1; k < points.size(); ++k) {
      canvas.Line(to_x(points[k - 1].first), to_y(points[k - 1].second), to_x(points[k].first),
                  to_y(points[k].second), colour, 2);
    }
  }
  return WritePng(path, w, h, 3, canvas.pixels(), error);
}

}  // namespace fleetmap
