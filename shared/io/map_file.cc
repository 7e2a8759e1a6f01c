#include "shared/io/map_file.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <png.h>
#include <yaml-cpp/yaml.h>

namespace fleetmap {
namespace {

// map_server's trinary values.
constexpr uint8_t kFreePixel = 254;
constexpr uint8_t kOccupiedPixel = 0;
constexpr uint8_t kUnknownPixel = 205;
// Larger images are refused rather than allocated: 40,000 x 40,000 cells is 2 km at 5 cm.
constexpr long kMaxPixels = 40000L * 40000L;

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

std::string ParentDir(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

// Reads the next whitespace-separated PGM header token, skipping '#' comments.
bool NextPgmToken(std::istream& in, std::string* token) {
  token->clear();
  int c;
  while ((c = in.get()) != EOF) {
    if (c == '#') {
      while ((c = in.get()) != EOF && c != '\n') {
      }
      continue;
    }
    if (std::isspace(c)) {
      if (!token->empty()) return true;
      continue;
    }
    token->push_back(static_cast<char>(c));
  }
  return !token->empty();
}

bool ParsePositiveInt(const std::string& s, long* value) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || end == s.c_str() || *end != '\0' || v <= 0) return false;
  *value = v;
  return true;
}

struct PngCloser {
  png_structp png = nullptr;
  png_infop info = nullptr;
  bool reading = true;
  ~PngCloser() {
    if (!png) return;
    if (reading) {
      png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    } else {
      png_destroy_write_struct(&png, info ? &info : nullptr);
    }
  }
};

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};

}  // namespace

bool ReadPgm(const std::string& path, GreyImage* image, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Fail(error, path + ": cannot open");
  std::string magic, w, h, maxval;
  if (!NextPgmToken(in, &magic) || (magic != "P5" && magic != "P2")) {
    return Fail(error, path + ": not a PGM image (expected P5 or P2)");
  }
  long width = 0, height = 0, max_value = 0;
  if (!NextPgmToken(in, &w) || !NextPgmToken(in, &h) || !NextPgmToken(in, &maxval) ||
      !ParsePositiveInt(w, &width) || !ParsePositiveInt(h, &height) ||
      !ParsePositiveInt(maxval, &max_value)) {
    return Fail(error, path + ": malformed PGM header");
  }
  if (max_value > 255) return Fail(error, path + ": 16-bit PGM images are not supported");
  if (width * height > kMaxPixels || width > kMaxPixels / height) {
    return Fail(error, path + ": image too large (" + w + " x " + h + ")");
  }
  image->width = static_cast<int>(width);
  image->height = static_cast<int>(height);
  image->pixels.assign(static_cast<size_t>(width * height), 0);
  if (magic == "P5") {
    in.read(reinterpret_cast<char*>(image->pixels.data()), static_cast<std::streamsize>(width * height));
    if (in.gcount() != width * height) return Fail(error, path + ": truncated PGM pixel data");
  } else {
    std::string token;
    for (auto& p : image->pixels) {
      long v = 0;
      if (!NextPgmToken(in, &token)) return Fail(error, path + ": truncated PGM pixel data");
      char* end = nullptr;
      v = std::strtol(token.c_str(), &end, 10);
      if (*end != '\0' || v < 0 || v > max_value) return Fail(error, path + ": bad PGM pixel " + token);
      p = static_cast<uint8_t>(v);
    }
  }
  if (max_value != 255) {
    for (auto& p : image->pixels) p = static_cast<uint8_t>(p * 255 / max_value);
  }
  return true;
}

bool WritePgm(const std::string& path, const GreyImage& image, std::string* error) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Fail(error, path + ": cannot write");
  out << "P5\n# CREATOR: fleetmap\n" << image.width << " " << image.height << "\n255\n";
  out.write(reinterpret_cast<const char*>(image.pixels.data()),
            static_cast<std::streamsize>(image.pixels.size()));
  if (!out) return Fail(error, path + ": write failed");
  return true;
}

bool ReadPng(const std::string& path, GreyImage* image, std::string* error) {
  std::unique_ptr<FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) return Fail(error, path + ": cannot open");
  png_byte header[8];
  if (std::fread(header, 1, 8, file.get()) != 8 || png_sig_cmp(header, 0, 8) != 0) {
    return Fail(error, path + ": not a PNG image");
  }
  PngCloser closer;
  closer.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!closer.png) return Fail(error, "libpng: out of memory");
  closer.info = png_create_info_struct(closer.png);
  if (!closer.info) return Fail(error, "libpng: out of memory");
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(closer.png))) return Fail(error, path + ": corrupt PNG image");
  png_init_io(closer.png, file.get());
  png_set_sig_bytes(closer.png, 8);
  png_set_user_limits(closer.png, 40000, 40000);
  png_read_info(closer.png, closer.info);
  // Normalise every PNG flavour to 8-bit grey, as map_server does (it averages colour channels).
  png_set_strip_16(closer.png);
  png_set_strip_alpha(closer.png);
  png_set_packing(closer.png);
  const png_byte color_type = png_get_color_type(closer.png, closer.info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(closer.png);
  if (color_type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(closer.png, closer.info) < 8) {
    png_set_expand_gray_1_2_4_to_8(closer.png);
  }
  if (color_type & PNG_COLOR_MASK_COLOR || color_type == PNG_COLOR_TYPE_PALETTE) {
    png_set_rgb_to_gray_fixed(closer.png, 1, 33333, 33333);
  }
  png_read_update_info(closer.png, closer.info);
  const png_uint_32 width = png_get_image_width(closer.png, closer.info);
  const png_uint_32 height = png_get_image_height(closer.png, closer.info);
  if (png_get_rowbytes(closer.png, closer.info) != width) {
    return Fail(error, path + ": unsupported PNG pixel format");
  }
  image->width = static_cast<int>(width);
  image->height = static_cast<int>(height);
  image->pixels.assign(static_cast<size_t>(width) * height, 0);
  rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image->pixels.data() + static_cast<size_t>(y) * width;
  png_read_image(closer.png, rows.data());
  return true;
}

bool WritePng(const std::string& path, int width, int height, int channels,
              const std::vector<uint8_t>& pixels, std::string* error) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
      pixels.size() != static_cast<size_t>(width) * height * channels) {
    return Fail(error, path + ": invalid image dimensions for PNG");
  }
  std::unique_ptr<FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) return Fail(error, path + ": cannot write");
  PngCloser closer;
  closer.reading = false;
  closer.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!closer.png) return Fail(error, "libpng: out of memory");
  closer.info = png_create_info_struct(closer.png);
  if (!closer.info) return Fail(error, "libpng: out of memory");
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  if (setjmp(png_jmpbuf(closer.png))) return Fail(error, path + ": PNG write failed");
  png_init_io(closer.png, file.get());
  // Fast compression: maps and camera frames are written often. Level 1 with the SUB filter
  // alone is about 2x faster than level 3 with adaptive filtering, at a similar size.
  png_set_compression_level(closer.png, 1);
  png_set_filter(closer.png, 0, PNG_FILTER_SUB);
  png_set_IHDR(closer.png, closer.info, static_cast<png_uint_32>(width),
               static_cast<png_uint_32>(height), 8,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(closer.png, closer.info);
  for (int y = 0; y < height; ++y) {
    rows[static_cast<size_t>(y)] =
        const_cast<png_bytep>(pixels.data() + static_cast<size_t>(y) * width * channels);
  }
  png_write_image(closer.png, rows.data());
  png_write_end(closer.png, nullptr);
  return true;
}

GreyImage GridToImage(const OccupancyGrid& grid, bool crop, Eigen::Vector2d* image_origin) {
  CellIndex lo(0, 0), hi(grid.width() - 1, grid.height() - 1);
  if (crop && !grid.KnownBounds(&lo, &hi)) {
    lo = CellIndex(0, 0);
    hi = CellIndex(0, 0);
  }
  if (grid.empty()) hi = CellIndex(0, 0);
  GreyImage image;
  image.width = hi.x() - lo.x() + 1;
  image.height = hi.y() - lo.y() + 1;
  image.pixels.assign(static_cast<size_t>(image.width) * image.height, kUnknownPixel);
  const MapMetadata defaults;
  for (int y = lo.y(); y <= hi.y(); ++y) {
    const int row = hi.y() - y;  // image rows run top (max y) to bottom
    for (int x = lo.x(); x <= hi.x(); ++x) {
      const CellIndex cell(x, y);
      if (!grid.IsKnown(cell)) continue;
      const float p = grid.Probability(cell);
      uint8_t value = kUnknownPixel;
      if (p > defaults.occupied_thresh) value = kOccupiedPixel;
      if (p < defaults.free_thresh) value = kFreePixel;
      image.pixels[static_cast<size_t>(row) * image.width + (x - lo.x())] = value;
    }
  }
  *image_origin = grid.origin() + grid.resolution() * lo.cast<double>().matrix();
  return image;
}

bool ReadMap(const std::string& yaml_path, OccupancyGrid* grid, std::string* error) {
  MapMetadata meta;
  try {
    const YAML::Node node = YAML::LoadFile(yaml_path);
    if (!node["image"]) return Fail(error, yaml_path + ": missing field 'image'");
    if (!node["resolution"]) return Fail(error, yaml_path + ": missing field 'resolution'");
    if (!node["origin"] || !node["origin"].IsSequence() || node["origin"].size() != 3) {
      return Fail(error, yaml_path + ": 'origin' must be a list [x, y, yaw]");
    }
    meta.image = node["image"].as<std::string>();
    meta.resolution = node["resolution"].as<double>();
    meta.origin = Eigen::Vector2d(node["origin"][0].as<double>(), node["origin"][1].as<double>());
    meta.origin_yaw = node["origin"][2].as<double>();
    if (node["negate"]) meta.negate = node["negate"].as<int>() != 0;
    if (node["occupied_thresh"]) meta.occupied_thresh = node["occupied_thresh"].as<double>();
    if (node["free_thresh"]) meta.free_thresh = node["free_thresh"].as<double>();
  } catch (const YAML::Exception& e) {
    return Fail(error, yaml_path + ": " + e.what());
  }
  if (!(meta.resolution > 0.0) || !std::isfinite(meta.resolution)) {
    return Fail(error, yaml_path + ": resolution must be positive");
  }
  if (!meta.origin.allFinite()) return Fail(error, yaml_path + ": origin must be finite");
  if (std::abs(meta.origin_yaw) > 1e-9) {
    return Fail(error, yaml_path + ": rotated map origins (yaw != 0) are not supported");
  }
  if (!(meta.free_thresh < meta.occupied_thresh)) {
    return Fail(error, yaml_path + ": free_thresh must be below occupied_thresh");
  }
  std::filesystem::path image_path(meta.image);
  if (image_path.is_relative()) image_path = std::filesystem::path(ParentDir(yaml_path)) / image_path;
  GreyImage image;
  const std::string ext = image_path.extension().string();
  const bool ok = (ext == ".png" || ext == ".PNG") ? ReadPng(image_path.string(), &image, error)
                                                   : ReadPgm(image_path.string(), &image, error);
  if (!ok) return false;

  OccupancyGridOptions options = grid->options();
  options.resolution = meta.resolution;
  OccupancyGrid result(options, meta.origin, image.width, image.height);
  for (int row = 0; row < image.height; ++row) {
    const int y = image.height - 1 - row;
    for (int x = 0; x < image.width; ++x) {
      const uint8_t v = image.pixels[static_cast<size_t>(row) * image.width + x];
      const double p = meta.negate ? v / 255.0 : (255.0 - v) / 255.0;
      if (p > meta.occupied_thresh) {
        result.SetLogOdds(CellIndex(x, y), options.log_odds_max);
      } else if (p < meta.free_thresh) {
        result.SetLogOdds(CellIndex(x, y), options.log_odds_min);
      }
    }
  }
  *grid = std::move(result);
  return true;
}

bool WriteMap(const std::string& stem, const OccupancyGrid& grid, std::string* error, bool crop) {
  Eigen::Vector2d origin;
  const GreyImage image = GridToImage(grid, crop, &origin);
  const std::string pgm_path = stem + ".pgm";
  if (!WritePgm(pgm_path, image, error)) return false;
  std::ofstream yaml(stem + ".yaml");
  if (!yaml) return Fail(error, stem + ".yaml: cannot write");
  const MapMetadata defaults;
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer),
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\nnegate: 0\n"
                "occupied_thresh: %.3f\nfree_thresh: %.3f\n",
                std::filesystem::path(pgm_path).filename().c_str(), grid.resolution(),
                origin.x(), origin.y(), defaults.occupied_thresh, defaults.free_thresh);
  yaml << buffer;
  if (!yaml) return Fail(error, stem + ".yaml: write failed");
  return true;
}

bool WriteMapPng(const std::string& path, const OccupancyGrid& grid, std::string* error,
                 bool crop) {
  Eigen::Vector2d origin;
  const GreyImage image = GridToImage(grid, crop, &origin);
  return WritePng(path, image.width, image.height, 1, image.pixels, error);
}

}  // namespace fleetmap
