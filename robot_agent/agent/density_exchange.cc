#include "robot_agent/agent/density_exchange.h"

#include <chrono>
#include <utility>

#include "robot_agent/agent/internal/status_codes.h"
#include "robot_agent/agent/proto_conversions.h"

namespace fleetmap {

DensityExchange::DensityExchange(const DensityExchangeOptions& options,
                                 std::shared_ptr<grpc::ChannelInterface> channel)
    : options_(options), stub_(v1::MapService::NewStub(channel)), random_(std::random_device()()) {}

DensityExchange::~DensityExchange() { Stop(); }

void DensityExchange::Start() {
  sender_ = std::thread([this] { SendLoop(); });
  subscriber_ = std::thread([this] { SubscribeLoop(); });
}

void DensityExchange::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    if (active_call_) active_call_->TryCancel();
  }
  wake_.notify_all();
  if (sender_.joinable()) sender_.join();
  if (subscriber_.joinable()) subscriber_.join();
}

void DensityExchange::Send(const PoseDensity& density) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (outgoing_.size() >= options_.queue_limit) {
      outgoing_.pop_front();
      ++stats_.dropped;
    }
    outgoing_.push_back(density);
  }
  wake_.notify_all();
}

std::vector<PoseDensity> DensityExchange::TakeReceived() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<PoseDensity> out;
  out.swap(received_);
  return out;
}

DensityExchangeStats DensityExchange::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

bool DensityExchange::Wait(double seconds) {
  std::unique_lock<std::mutex> lock(mutex_);
  return !wake_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return stop_; });
}

void DensityExchange::SendLoop() {
  while (true) {
    PoseDensity density;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !outgoing_.empty(); });
      if (stop_) return;
      density = std::move(outgoing_.front());
      outgoing_.pop_front();
    }
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() +
                         std::chrono::milliseconds(static_cast<int>(options_.rpc_timeout * 1000)));
    v1::SendPoseDensityResponse response;
    const grpc::Status status =
        stub_->SendPoseDensity(&context, agent::ToProto(density), &response);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!status.ok()) {
      ++stats_.send_failed;
    } else {
      ++stats_.sent;
      if (response.receivers() > 0) ++stats_.delivered;
    }
  }
}

void DensityExchange::SubscribeLoop() {
  int failures = 0;
  while (true) {
    grpc::ClientContext context;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
      active_call_ = &context;
    }
    v1::SubscribePoseDensitiesRequest request;
    request.set_robot_id(options_.robot_id);
    std::unique_ptr<grpc::ClientReader<v1::PoseDensity>> reader =
        stub_->SubscribePoseDensities(&context, request);
    // The server marks a subscription that took in its first metadata (a refused call has none).
    reader->WaitForInitialMetadata();
    if (context.GetServerInitialMetadata().count("fleetmap-density-subscribed") > 0) {
      subscribed_ = true;
      failures = 0;
    }
    v1::PoseDensity message;
    while (reader->Read(&message)) {
      PoseDensity density;
      std::lock_guard<std::mutex> lock(mutex_);
      if (!agent::FromProto(message, &density) || density.observed_id != options_.robot_id) {
        continue;  // the server checks densities; this guards against a misrouted one
      }
      if (received_.size() >= options_.queue_limit) {
        received_.erase(received_.begin());
        ++stats_.dropped;
      }
      received_.push_back(std::move(density));
      ++stats_.received;
    }
    reader->Finish();
    subscribed_ = false;
    double wait;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      active_call_ = nullptr;
      if (stop_) return;
      // Until the uploader has registered the robot the server answers NOT_FOUND: retry.
      wait = BackoffDelay(options_.reconnect, ++failures,
                          std::uniform_real_distribution<double>(0.0, 1.0)(random_));
    }
    if (!Wait(wait)) return;
  }
}

}  // namespace fleetmap
