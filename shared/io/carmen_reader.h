#ifndef FLEETMAP_SHARED_IO_CARMEN_READER_H_
#define FLEETMAP_SHARED_IO_CARMEN_READER_H_

#include <memory>
#include <string>

#include "shared/io/carmen_log.h"

namespace fleetmap {

struct CarmenReaderOptions {
  // Count and skip malformed lines instead of stopping at the first one.
  bool skip_bad_lines = false;
  // Largest beam count accepted on one line; more is treated as corrupt, not allocated.
  int max_beams = 10000;
};

// Streams a CARMEN log (.clf/.log plain, .gz or .bz2, detected from the content) one record at a
// time. Unknown message types and comments are skipped silently; malformed known messages are
// errors naming the file and line number. Never reads out of bounds, whatever the input.
class CarmenReader {
 public:
  // Returns nullptr and fills `error` when the file cannot be opened.
  static std::unique_ptr<CarmenReader> Open(const std::string& path,
                                            const CarmenReaderOptions& options,
                                            std::string* error);
  virtual ~CarmenReader() = default;

  // Reads the next record. Returns false at the end of the log or on an error; tell them apart
  // with error(). With skip_bad_lines, malformed lines are counted and skipped instead.
  virtual bool Next(CarmenRecord* record) = 0;
  // Empty unless reading stopped on an error, e.g. "intel.clf.bz2:1234: FLASER: expected 180
  // ranges, found 17".
  virtual const std::string& error() const = 0;
  virtual long line_number() const = 0;
  virtual long skipped_lines() const = 0;
  // The first skipped line's message (for reporting), empty when none.
  virtual const std::string& first_skipped_error() const = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_READER_H_
