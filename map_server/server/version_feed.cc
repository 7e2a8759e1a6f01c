#include "map_server/server/version_feed.h"

namespace fleetmap {

void VersionFeed::Publish(std::shared_ptr<const GlobalMapSnapshot> snapshot) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = std::move(snapshot);
  }
  changed_.notify_all();
}

std::shared_ptr<const GlobalMapSnapshot> VersionFeed::Latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

std::shared_ptr<const GlobalMapSnapshot> VersionFeed::WaitNewer(
    int64_t after_version, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto newer = [&] { return latest_ && latest_->info.version > after_version; };
  changed_.wait_for(lock, timeout, [&] { return closed_ || newer(); });
  if (closed_ || !newer()) return nullptr;
  return latest_;
}

void VersionFeed::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool VersionFeed::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

}  // namespace fleetmap
