#include "map_server/server/density_relay.h"

namespace fleetmap {

std::optional<v1::PoseDensity> DensityRelay::Subscription::Pop(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!ready_.wait_for(lock, timeout, [&] { return !queue_.empty() || closed_; }) ||
      queue_.empty()) {
    return std::nullopt;
  }
  v1::PoseDensity density = std::move(queue_.front());
  queue_.pop_front();
  return density;
}

int64_t DensityRelay::Subscription::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

std::shared_ptr<DensityRelay::Subscription> DensityRelay::Subscribe(const std::string& robot_id) {
  auto subscription = std::make_shared<Subscription>();
  std::lock_guard<std::mutex> lock(mutex_);
  subscription->closed_ = closed_;
  subscriptions_.emplace(robot_id, subscription);
  return subscription;
}

void DensityRelay::Unsubscribe(const std::string& robot_id,
                               const std::shared_ptr<Subscription>& subscription) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto [begin, end] = subscriptions_.equal_range(robot_id);
  for (auto it = begin; it != end; ++it) {
    if (it->second == subscription) {
      subscriptions_.erase(it);
      return;
    }
  }
}

int DensityRelay::Publish(const v1::PoseDensity& density) {
  std::lock_guard<std::mutex> lock(mutex_);
  int receivers = 0;
  auto [begin, end] = subscriptions_.equal_range(density.observed_id());
  for (auto it = begin; it != end; ++it) {
    Subscription& subscription = *it->second;
    {
      std::lock_guard<std::mutex> queue_lock(subscription.mutex_);
      if (subscription.queue_.size() >= queue_limit_) {
        subscription.queue_.pop_front();
        ++subscription.dropped_;
      }
      subscription.queue_.push_back(density);
    }
    subscription.ready_.notify_one();
    ++receivers;
  }
  return receivers;
}

void DensityRelay::Close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  for (auto& [robot, subscription] : subscriptions_) {
    {
      std::lock_guard<std::mutex> queue_lock(subscription->mutex_);
      subscription->closed_ = true;
    }
    subscription->ready_.notify_all();
  }
}

bool DensityRelay::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

}  // namespace fleetmap
