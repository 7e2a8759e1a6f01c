#ifndef FLEETMAP_SHARED_IO_NUMBER_ROWS_FILE_H_
#define FLEETMAP_SHARED_IO_NUMBER_ROWS_FILE_H_

#include <functional>
#include <string>

namespace fleetmap {

// Reads a text file (plain, .gz or .bz2) of whitespace-separated finite numbers, `columns` on
// every line; blank lines and lines starting with '#' are skipped. `row` gets each line's
// values. On a malformed line it stops and returns false, with "path:line: what" in *error;
// `layout` names the columns for that message, e.g. "timestamp x y theta".
bool ReadNumberRows(const std::string& path, int columns, const std::string& layout,
                    const std::function<void(const double* values)>& row, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_NUMBER_ROWS_FILE_H_
