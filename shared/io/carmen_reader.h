#ifndef FLEETMAP_SHARED_IO_CARMEN_READER_H_
#define FLEETMAP_SHARED_IO_CARMEN_READER_H_

#include <map>
#include <memory>
#include <string>

#include "shared/io/carmen_log.h"

namespace fleetmap {

struct CarmenReaderOptions {
  // Count and skip malformed lines instead of stopping at the first one.
  bool skip_bad_lines = false;
  // Largest beam count accepted on one line; more is treated as corrupt, not allocated.
  int max_beams = 10000;
  // Readings at or above this range (metres) are "no return". FLASER lines carry no maximum
  // range, so one is needed: 50 m turns the SICK overflow codes (81.83/81.91 m in intel, fr079,
  // csail; 81.81..81.83 m in fr-clinic), aces' 50.00 m saturation and mit-killian's 51.1 m into
  // no-returns, while every real return in those logs lies below 50 m (intel 26 m, fr079 37 m,
  // csail 42 m, aces 49.9 m). ROBOTLASER1 lines use the smaller of this and their own max_range.
  double max_range = 50.0;
  // A `PARAM robot_front_laser_max <m>` line replaces `max_range` for the lines after it (the
  // CarmenWriter writes one so that its logs read back exactly).
  bool max_range_from_params = true;
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
  // Lines read so far per message type ("FLASER", "ODOM", unknown types too; "#" counts
  // comments), whether they parsed or not.
  virtual const std::map<std::string, long>& message_counts() const;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_READER_H_
