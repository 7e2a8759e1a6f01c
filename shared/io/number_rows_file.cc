#include "shared/io/number_rows_file.h"

#include <cmath>
#include <memory>
#include <vector>

#include "shared/io/carmen_parse.h"
#include "shared/io/decompressing_stream.h"

namespace fleetmap {

bool ReadNumberRows(const std::string& path, int columns, const std::string& layout,
                    const std::function<void(const double* values)>& row, std::string* error) {
  const auto fail = [error](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  std::string open_error;
  std::unique_ptr<DecompressingStream> stream = DecompressingStream::Open(path, &open_error);
  if (!stream) return fail(open_error);
  const size_t count = static_cast<size_t>(columns);
  std::vector<double> values(count);
  carmen::Tokens tokens;
  std::string_view line;
  long line_number = 0;
  while (stream->NextLine(&line)) {
    ++line_number;
    carmen::SplitTokens(line, &tokens);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (tokens.size() != count) {
      return fail(where + "expected " + std::to_string(columns) + " values '" + layout +
                  "', found " + std::to_string(tokens.size()));
    }
    for (size_t i = 0; i < count; ++i) {
      if (!carmen::ParseDouble(tokens[i], &values[i])) {
        return fail(where + "value " + std::to_string(i + 1) + " '" +
                    std::string(tokens[i].substr(0, 20)) + "' is not a number");
      }
      if (!std::isfinite(values[i])) {
        return fail(where + "value " + std::to_string(i + 1) + " is not finite");
      }
    }
    row(values.data());
  }
  if (!stream->error().empty()) {
    return fail(path + ":" + std::to_string(line_number + 1) + ": " + stream->error());
  }
  return true;
}

}  // namespace fleetmap
