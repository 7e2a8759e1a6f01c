#ifndef FLEETMAP_MAP_SERVER_MERGE_MAP_SYMMETRIES_H_
#define FLEETMAP_MAP_SERVER_MERGE_MAP_SYMMETRIES_H_

#include <vector>

#include <Eigen/Core>

#include "map_server/merge/match_target.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// When a map fits itself moved (a building turned half round, a row of identical offices), any
// alignment of another map onto it has a twin: the same alignment followed by that move. Where
// the twin lands the other map on space this map has not seen, nothing in the maps can tell the
// two apart, however well the first fits; the map's own symmetries are how to find the twin.
struct MapSymmetryOptions {
  // A symmetry lands at least this share of the map's points on space the map observed ...
  double min_overlap = 0.25;
  // ... scores there at least this share of the map's score at no move ...
  double min_overlap_score = 0.85;
  // ... and puts fewer than this many of the map's walls in space the map saw free (walls seen
  // through rule a move out, as they rule out alignments of two maps; MergeEngineOptions).
  int max_contradictions = 30;
  // The best this many distinct moves are examined, best scoring over all points first.
  int max_examined = 32;
  // Moves within this of no move, or of one already found, are not distinct.
  ExclusionZone distinct;
  // Gates of the fits judged (their minimums are not applied).
  MatchGates gates;
};

// The moves S (map frame to map frame, S != identity) under which the map `target` fits itself.
// `source` holds the map's own points (MakeMatchSource of the same grid at the identity);
// `walls` the wall points whose crossing of seen-free space counts against a move (the map's
// points, less any the caller excuses, in the map's frame).
std::vector<Rigid2d> MapSymmetries(const MatchTarget& target, const MatchSource& source,
                                   const std::vector<Eigen::Vector2d>& walls,
                                   const MapSymmetryOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_MAP_SYMMETRIES_H_
