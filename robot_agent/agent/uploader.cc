#include "robot_agent/agent/uploader.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "robot_agent/agent/internal/status_codes.h"

namespace fleetmap {
using internal::Describe;

double UnixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

const char* ConnectionStateName(ConnectionState state) {
  switch (state) {
    case ConnectionState::kConnecting:
      return "connecting";
    case ConnectionState::kConnected:
      return "connected";
    case ConnectionState::kDisconnected:
      return "disconnected";
  }
  return "unknown";
}

Uploader::Uploader(const UploaderOptions& options, Outbox* outbox,
                   std::shared_ptr<grpc::ChannelInterface> channel,
                   const v1::RegisterRobotRequest& registration, std::function<double()> clock)
    : options_(options),
      outbox_(outbox),
      stub_(v1::MapService::NewStub(channel)),
      registration_(registration),
      clock_(clock ? std::move(clock) : std::function<double()>(UnixNow)),
      random_(std::random_device()()) {}

Uploader::~Uploader() { Stop(); }

void Uploader::Start() {
  std::string error;
  // A restart is a fresh start: whatever waited for a retry is due now.
  if (!outbox_->MakeAllDue(clock_(), &error)) NoteError(error);
  thread_ = std::thread([this] { Loop(); });
}

void Uploader::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    if (active_call_) active_call_->TryCancel();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Uploader::Notify() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    notified_ = true;
  }
  wake_.notify_all();
}

bool Uploader::WaitUntilEmpty(double timeout) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(std::max(0.0, timeout)));
  while (true) {
    OutboxCounts counts;
    std::string error;
    // Under the lock Acknowledge holds while it removes and counts: empty means counted too.
    std::unique_lock<std::mutex> lock(mutex_);
    if (outbox_->Counts(&counts, &error) && counts.pending == 0) return true;
    if (Clock::now() >= deadline) return false;
    // Woken after every round; the short cap also covers rounds that ended before we waited.
    progress_.wait_until(lock, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
  }
}

UploaderStats Uploader::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

double Uploader::Delay(int attempt) {
  return BackoffDelay(options_.backoff, attempt,
                      std::uniform_real_distribution<double>(0.0, 1.0)(random_));
}

void Uploader::NoteError(const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.last_error = message;
}

void Uploader::Loop() {
  while (true) {
    const Round round = RunRound();
    double wait = 0.0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) break;
      if (round == Round::kFailed) {
        ++consecutive_failures_;
        stats_.state = ConnectionState::kDisconnected;
        wait = Delay(consecutive_failures_);
      } else if (round == Round::kIdle) {
        wait = options_.idle_poll;
      }
    }
    progress_.notify_all();
    if (round == Round::kIdle) {
      double next_due = 0.0;
      std::string error;
      if (outbox_->NextDueTime(&next_due, &error)) {
        wait = std::clamp(next_due - clock_(), 0.0, options_.idle_poll);
      }
    }
    if (wait <= 0.0) continue;
    std::unique_lock<std::mutex> lock(mutex_);
    // A notification ends an idle wait, never a backoff.
    wake_.wait_for(lock, std::chrono::duration<double>(wait),
                   [&] { return stop_ || (round == Round::kIdle && notified_); });
    notified_ = false;
    if (stop_) break;
  }
  progress_.notify_all();
}

Uploader::Round Uploader::RunRound() {
  if (!stats().registered && !Register()) return Round::kFailed;
  bool progress = false;
  for (OutboxKind kind : {OutboxKind::kSubmap, OutboxKind::kTrajectory, OutboxKind::kDetection}) {
    int limit;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return Round::kIdle;
      limit = single_item_rounds_ > 0 ? 1 : std::max(1, options_.max_batch_items);
      if (kind == OutboxKind::kTrajectory) limit = 1;
    }
    std::vector<OutboxItem> items;
    std::string error;
    if (!outbox_->Due(kind, clock_(), limit, options_.max_batch_bytes, &items, &error)) {
      NoteError(error);
      return Round::kFailed;
    }
    if (items.empty()) continue;
    Outcome outcome;
    switch (kind) {
      case OutboxKind::kSubmap:
        outcome = SendSubmaps(items);
        break;
      case OutboxKind::kTrajectory:
        outcome = SendTrajectory(items.front());
        break;
      default:
        outcome = SendDetections(items);
        break;
    }
    if (outcome == Outcome::kFailed) return Round::kFailed;
    progress = true;
  }
  if (progress) {
    std::string error;
    std::lock_guard<std::mutex> lock(mutex_);
    if (consecutive_failures_ > 0 || stats_.state != ConnectionState::kConnected) {
      // Back from an outage: what was held back by per-item backoff goes now.
      outbox_->MakeAllDue(clock_(), &error);
    }
    consecutive_failures_ = 0;
    stats_.state = ConnectionState::kConnected;
    if (single_item_rounds_ > 0) --single_item_rounds_;
  }
  return progress ? Round::kProgress : Round::kIdle;
}

grpc::Status Uploader::Call(grpc::ClientContext* context,
                            const std::function<grpc::Status()>& rpc) {
  context->set_deadline(
      std::chrono::system_clock::now() +
      std::chrono::microseconds(static_cast<int64_t>(options_.rpc_timeout * 1e6)));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return grpc::Status::CANCELLED;
    // Stop() cancels it from another thread (also when it has not started yet).
    active_call_ = context;
  }
  const grpc::Status status = rpc();
  std::lock_guard<std::mutex> lock(mutex_);
  active_call_ = nullptr;
  return status;
}

bool Uploader::Register() {
  grpc::ClientContext context;
  v1::RegisterRobotResponse response;
  const grpc::Status status =
      Call(&context, [&] { return stub_->RegisterRobot(&context, registration_, &response); });
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status.ok()) {
    ++stats_.failed_calls;
    stats_.last_error = "RegisterRobot: " + Describe(status);
    return false;
  }
  stats_.registered = true;
  stats_.state = ConnectionState::kConnected;
  return true;
}

}  // namespace fleetmap
