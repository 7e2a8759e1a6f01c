#ifndef FLEETMAP_MAP_SERVER_SERVER_DENSITY_RELAY_H_
#define FLEETMAP_MAP_SERVER_SERVER_DENSITY_RELAY_H_

#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "proto/fleetmap/v1/fleetmap.pb.h"

namespace fleetmap {

// Live fan-out of pose densities (collaborative localization) from the robot that saw another to
// that robot's subscriptions. Nothing is stored: a density is only worth applying while fresh,
// so a robot that is not listening misses it, and a subscriber that falls behind loses the
// oldest ones first. Thread-safe.
class DensityRelay {
 public:
  class Subscription {
   public:
    // The next density, or nullopt after `timeout` or once the relay is closed.
    std::optional<v1::PoseDensity> Pop(std::chrono::milliseconds timeout);
    int64_t dropped() const;

   private:
    friend class DensityRelay;
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<v1::PoseDensity> queue_;
    int64_t dropped_ = 0;
    bool closed_ = false;
  };

  explicit DensityRelay(size_t queue_limit = 64) : queue_limit_(queue_limit) {}

  std::shared_ptr<Subscription> Subscribe(const std::string& robot_id);
  void Unsubscribe(const std::string& robot_id, const std::shared_ptr<Subscription>& subscription);
  // Delivers to every subscription of density.observed_id(); returns how many.
  int Publish(const v1::PoseDensity& density);
  // Ends every subscription (server shutdown).
  void Close();
  bool closed() const;

 private:
  const size_t queue_limit_;
  mutable std::mutex mutex_;  // guards subscriptions_ and closed_
  std::multimap<std::string, std::shared_ptr<Subscription>> subscriptions_;
  bool closed_ = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_DENSITY_RELAY_H_
