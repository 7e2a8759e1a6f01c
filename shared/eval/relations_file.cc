#include "shared/eval/relations_file.h"

#include <cmath>
#include <memory>

#include "shared/io/carmen_parse.h"
#include "shared/io/decompressing_stream.h"

namespace fleetmap {

bool ReadRelations(const std::string& path, std::vector<Relation>* relations, std::string* error) {
  std::string open_error;
  std::unique_ptr<DecompressingStream> stream = DecompressingStream::Open(path, &open_error);
  if (!stream) {
    if (error) *error = open_error;
    return false;
  }
  relations->clear();
  carmen::Tokens tokens;
  std::string_view line;
  long line_number = 0;
  while (stream->NextLine(&line)) {
    ++line_number;
    carmen::SplitTokens(line, &tokens);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (tokens.size() != 8) {
      if (error) {
        *error = where + "expected 8 values 't1 t2 x y z roll pitch yaw', found " +
                 std::to_string(tokens.size());
      }
      return false;
    }
    double v[8];
    for (size_t i = 0; i < 8; ++i) {
      if (!carmen::ParseDouble(tokens[i], &v[i]) || !std::isfinite(v[i])) {
        if (error) {
          *error = where + "value " + std::to_string(i + 1) + " '" +
                   std::string(tokens[i].substr(0, 20)) + "' is not a finite number";
        }
        return false;
      }
    }
    relations->push_back(Relation{v[0], v[1], Rigid2d(v[2], v[3], v[7])});
  }
  if (!stream->error().empty()) {
    if (error) *error = path + ":" + std::to_string(line_number + 1) + ": " + stream->error();
    return false;
  }
  return true;
}

}  // namespace fleetmap
