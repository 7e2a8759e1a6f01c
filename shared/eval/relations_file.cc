#include "shared/eval/relations_file.h"

#include "shared/io/number_rows_file.h"

namespace fleetmap {

bool ReadRelations(const std::string& path, std::vector<Relation>* relations, std::string* error) {
  relations->clear();
  return ReadNumberRows(
      path, 8, "t1 t2 x y z roll pitch yaw",
      [&](const double* v) {
        relations->push_back(Relation{v[0], v[1], Rigid2d(v[2], v[3], v[7])});
      },
      error);
}

}  // namespace fleetmap
