#ifndef FLEETMAP_MAP_SERVER_SERVER_VERSION_FEED_H_
#define FLEETMAP_MAP_SERVER_SERVER_VERSION_FEED_H_

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "map_server/store/records.h"
#include "shared/codec/grid_codec.h"

namespace fleetmap {

// One published global map version, immutable once published; shared by query handlers and
// subscriptions without copying.
struct GlobalMapSnapshot {
  VersionRecord info;
  QuantizedGrid grid;   // the cells, for crops and resampling
  EncodedGrid encoded;  // the whole map as compressed once, served as it is
};

// The latest published version, and a way to wait for the next one. The merge worker publishes;
// handlers read. Thread-safe.
class VersionFeed {
 public:
  void Publish(std::shared_ptr<const GlobalMapSnapshot> snapshot);
  std::shared_ptr<const GlobalMapSnapshot> Latest() const;
  // The latest snapshot once its version exceeds `after_version`; nullptr on timeout or close.
  std::shared_ptr<const GlobalMapSnapshot> WaitNewer(int64_t after_version,
                                                     std::chrono::milliseconds timeout);
  // Wakes every waiter for good (server shutdown).
  void Close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;  // guards latest_ and closed_
  std::condition_variable changed_;
  std::shared_ptr<const GlobalMapSnapshot> latest_;
  bool closed_ = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_VERSION_FEED_H_
