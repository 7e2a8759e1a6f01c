#include "robot_agent/sim/world_io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "shared/core/occupancy_grid.h"
#include "shared/io/map_file.h"

namespace fleetmap::sim {
namespace {

std::string Fmt(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6f", value);
  return buffer;
}

bool ReadVector2(const YAML::Node& node, Eigen::Vector2d* out) {
  if (!node || !node.IsSequence() || node.size() != 2) return false;
  *out = Eigen::Vector2d(node[0].as<double>(), node[1].as<double>());
  return true;
}

bool LoadGrid(const std::string& map_yaml, World* world, std::string* error) {
  OccupancyGrid grid;
  std::string map_error;
  if (!ReadMap(map_yaml, &grid, &map_error)) {
    *error = "cannot read world map: " + map_error;
    return false;
  }
  World loaded(grid.resolution(), grid.origin(), grid.width(), grid.height());
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const float log_odds = grid.LogOdds(CellIndex(x, y));
      loaded.SetState(x, y,
                      log_odds > 0.0f   ? CellState::kOccupied
                      : log_odds < 0.0f ? CellState::kFree
                                        : CellState::kUnknown);
    }
  }
  loaded.name = std::filesystem::path(map_yaml).stem().string();
  *world = std::move(loaded);
  return true;
}

bool LoadMetadata(const YAML::Node& root, const std::string& path, World* world,
                  std::string* error) {
  if (root["name"]) world->name = root["name"].as<std::string>();
  if (root["wall_height"]) world->wall_height = root["wall_height"].as<double>();
  if (!(world->wall_height > 0.0)) {
    *error = path + ": wall_height must be positive";
    return false;
  }
  for (const YAML::Node& node : root["places"]) {
    Place place;
    place.name = node["name"].as<std::string>("");
    if (place.name.empty() || !node["x"] || !node["y"]) {
      *error = path + ": every place needs name, x and y";
      return false;
    }
    place.position = Eigen::Vector2d(node["x"].as<double>(), node["y"].as<double>());
    place.heading = node["heading"].as<double>(0.0);
    world->places.push_back(place);
  }
  for (const YAML::Node& node : root["patches"]) {
    WallPatch patch;
    patch.label = node["label"].as<std::string>("");
    const YAML::Node color = node["color"];
    if (!ReadVector2(node["min"], &patch.min) || !ReadVector2(node["max"], &patch.max) ||
        !color || !color.IsSequence() || color.size() != 3) {
      *error = path + ": patch '" + patch.label + "' needs min [x, y], max [x, y], color [r, g, b]";
      return false;
    }
    patch.z_min = node["z_min"].as<double>(0.0);
    patch.z_max = node["z_max"].as<double>(world->wall_height);
    patch.color = Rgb{static_cast<uint8_t>(color[0].as<int>()),
                      static_cast<uint8_t>(color[1].as<int>()),
                      static_cast<uint8_t>(color[2].as<int>())};
    world->patches.push_back(patch);
  }
  return true;
}

}  // namespace

bool LoadWorld(const std::string& path, World* world, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = "cannot read world file " + path + ": " + e.what();
    return false;
  }
  try {
    if (root["image"]) return LoadGrid(path, world, error);
    if (!root["map"]) {
      *error = path + ": a world file needs 'map: <map_server yaml>' (or is itself a map yaml)";
      return false;
    }
    const std::filesystem::path map_path =
        std::filesystem::path(path).parent_path() / root["map"].as<std::string>();
    if (!LoadGrid(map_path.string(), world, error)) return false;
    return LoadMetadata(root, path, world, error);
  } catch (const YAML::Exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
}

bool SaveWorld(const std::string& dir, const World& world, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::string stem = (std::filesystem::path(dir) / world.name).string();
  GreyImage image;
  image.width = world.width();
  image.height = world.height();
  image.pixels.resize(static_cast<size_t>(image.width) * static_cast<size_t>(image.height));
  for (int row = 0; row < image.height; ++row) {
    const int y = image.height - 1 - row;
    for (int x = 0; x < image.width; ++x) {
      const CellState state = world.State(x, y);
      image.pixels[static_cast<size_t>(row) * image.width + x] =
          state == CellState::kFree ? 254 : state == CellState::kOccupied ? 0 : 205;
    }
  }
  if (!WritePgm(stem + ".pgm", image, error)) return false;

  std::ofstream map_yaml(stem + ".yaml");
  map_yaml << "image: " << world.name << ".pgm\n"
           << "resolution: " << Fmt(world.resolution()) << "\n"
           << "origin: [" << Fmt(world.origin().x()) << ", " << Fmt(world.origin().y())
           << ", 0.0]\n"
           << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  std::ofstream meta(stem + ".world.yaml");
  meta << "# fleetmap simulator world: metadata a PGM cannot hold (see robot_agent/sim/README.md)\n"
       << "name: " << world.name << "\n"
       << "map: " << world.name << ".yaml\n"
       << "wall_height: " << Fmt(world.wall_height) << "\n"
       << "places:" << (world.places.empty() ? " []\n" : "\n");
  for (const Place& place : world.places) {
    meta << "  - {name: " << place.name << ", x: " << Fmt(place.position.x())
         << ", y: " << Fmt(place.position.y()) << ", heading: " << Fmt(place.heading) << "}\n";
  }
  meta << "patches:" << (world.patches.empty() ? " []\n" : "\n");
  for (const WallPatch& patch : world.patches) {
    meta << "  - {label: " << patch.label << ", min: [" << Fmt(patch.min.x()) << ", "
         << Fmt(patch.min.y()) << "], max: [" << Fmt(patch.max.x()) << ", " << Fmt(patch.max.y())
         << "], z_min: " << Fmt(patch.z_min) << ", z_max: " << Fmt(patch.z_max) << ", color: ["
         << int(patch.color.r) << ", " << int(patch.color.g) << ", " << int(patch.color.b)
         << "]}\n";
  }
  map_yaml.close();
  meta.close();
  if (!map_yaml || !meta) {
    *error = "cannot write world files " + stem + ".yaml / .world.yaml";
    return false;
  }
  return true;
}

}  // namespace fleetmap::sim
