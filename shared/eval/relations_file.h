#ifndef FLEETMAP_SHARED_EVAL_RELATIONS_FILE_H_
#define FLEETMAP_SHARED_EVAL_RELATIONS_FILE_H_

#include <string>
#include <vector>

#include "shared/eval/relations_metric.h"

namespace fleetmap {

// Reads a benchmark relations file: one relation per line, "t1 t2 x y z roll pitch yaw"
// (z, roll and pitch are 0 in 2D and ignored); '#' lines and blank lines are skipped. Plain,
// .gz or .bz2. Fills `error` with "file:line: message" on the first malformed line.
bool ReadRelations(const std::string& path, std::vector<Relation>* relations, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_RELATIONS_FILE_H_
