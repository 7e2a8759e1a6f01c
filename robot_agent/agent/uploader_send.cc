// The uploader's calls and what it does with their answers.
#include <cstdio>
#include <string>
#include <vector>

#include "robot_agent/agent/internal/status_codes.h"
#include "robot_agent/agent/uploader.h"

namespace fleetmap {

using internal::Describe;
using internal::IsRetryable;

namespace {

// The server holds a newer revision of this submap or trajectory (e.g. a restarted agent
// replays its data): this one is obsolete, not refused.
bool IsSuperseded(const OutboxItem& item, grpc::StatusCode code) {
  return code == grpc::StatusCode::FAILED_PRECONDITION &&
         (item.key.kind == OutboxKind::kSubmap || item.key.kind == OutboxKind::kTrajectory);
}

// Parses each item's payload into a new element of `batch`; an unreadable payload goes to
// `reject` instead. Returns the items that made it into the batch, in batch order.
template <typename Message, typename Reject>
std::vector<OutboxItem> ParseBatch(const std::vector<OutboxItem>& items,
                                   google::protobuf::RepeatedPtrField<Message>* batch,
                                   Reject reject) {
  std::vector<OutboxItem> parsed;
  for (const OutboxItem& item : items) {
    if (!batch->Add()->ParseFromString(item.payload)) {
      batch->RemoveLast();
      reject(item);
      continue;
    }
    parsed.push_back(item);
  }
  return parsed;
}

}  // namespace

void Uploader::DropSuperseded(const std::vector<OutboxItem>& items) {
  if (items.empty()) return;
  std::vector<int64_t> seqs;
  for (const OutboxItem& item : items) seqs.push_back(item.seq);
  std::string error;
  std::unique_lock<std::mutex> lock(mutex_);  // removed and counted in one step (Acknowledge)
  if (!outbox_->Acknowledge(seqs, &error)) {
    lock.unlock();
    NoteError(error);
    return;
  }
  stats_.superseded += static_cast<int64_t>(items.size());
}

void Uploader::RetryLater(const OutboxItem& item, const std::string& message) {
  std::string error;
  if (!outbox_->RecordFailure(item.seq, clock_() + Delay(item.attempts + 1), message, &error)) {
    NoteError(error);
  }
}

void Uploader::RejectItem(const OutboxItem& item, int code, const std::string& message) {
  std::fprintf(stderr, "fleetmap-agent: server refused %s %lld rev %lld for good: %s\n",
               OutboxKindName(item.key.kind), static_cast<long long>(item.key.id),
               static_cast<long long>(item.key.revision), message.c_str());
  std::string error;
  std::unique_lock<std::mutex> lock(mutex_);  // set aside and counted in one step (Acknowledge)
  const bool stored = outbox_->Reject(item.seq, code, message, &error);
  ++stats_.rejected;
  lock.unlock();
  if (!stored) NoteError(error);
}

void Uploader::Acknowledge(const std::vector<OutboxItem>& items, int64_t duplicates) {
  if (items.empty()) return;
  std::vector<int64_t> seqs;
  for (const OutboxItem& item : items) seqs.push_back(item.seq);
  std::string error;
  // Removed from the outbox and counted in one step, so that whoever sees the outbox empty
  // (WaitUntilEmpty, under the same lock) also sees the counts.
  std::unique_lock<std::mutex> lock(mutex_);
  if (!outbox_->Acknowledge(seqs, &error)) {
    lock.unlock();
    // Still queued: they will be sent again and acknowledged as duplicates.
    NoteError(error);
    return;
  }
  stats_.duplicates += duplicates;
  for (const OutboxItem& item : items) {
    switch (item.key.kind) {
      case OutboxKind::kSubmap:
        ++stats_.acked_submaps;
        break;
      case OutboxKind::kTrajectory:
        ++stats_.acked_trajectories;
        break;
      case OutboxKind::kDetection:
        ++stats_.acked_detections;
        break;
    }
  }
}

void Uploader::ApplyAcks(const std::vector<OutboxItem>& items,
                         const google::protobuf::RepeatedPtrField<v1::ItemAck>& acks) {
  std::vector<OutboxItem> stored;
  std::vector<OutboxItem> superseded;
  int64_t duplicates = 0;
  for (size_t i = 0; i < items.size(); ++i) {
    if (static_cast<int>(i) >= acks.size()) {
      RetryLater(items[i], "no acknowledgement for this item");
      continue;
    }
    const v1::ItemAck& ack = acks[static_cast<int>(i)];
    const auto code = static_cast<grpc::StatusCode>(ack.code());
    if (code == grpc::StatusCode::OK || code == grpc::StatusCode::ALREADY_EXISTS) {
      stored.push_back(items[i]);
      if (ack.duplicate()) ++duplicates;
    } else if (IsSuperseded(items[i], code)) {
      superseded.push_back(items[i]);
    } else if (IsRetryable(code)) {
      RetryLater(items[i], ack.message());
    } else {
      RejectItem(items[i], ack.code(), ack.message());
    }
  }
  Acknowledge(stored, duplicates);
  DropSuperseded(superseded);
}

Uploader::Outcome Uploader::HandleCallFailure(const grpc::Status& status,
                                              const std::vector<OutboxItem>& items) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.failed_calls;
    stats_.last_error = Describe(status);
    // The server lost the robot (e.g. a fresh database): register again before retrying.
    if (status.error_code() == grpc::StatusCode::NOT_FOUND) stats_.registered = false;
  }
  if (status.error_code() == grpc::StatusCode::NOT_FOUND || IsRetryable(status.error_code())) {
    for (const OutboxItem& item : items) RetryLater(item, status.error_message());
    return Outcome::kFailed;
  }
  if (items.size() == 1 && IsSuperseded(items[0], status.error_code())) {
    DropSuperseded(items);
    return Outcome::kOk;
  }
  if (items.size() > 1) {
    // The batch as a whole was refused (e.g. too large): find the culprit one item at a time.
    std::lock_guard<std::mutex> lock(mutex_);
    single_item_rounds_ = static_cast<int>(items.size());
    return Outcome::kOk;
  }
  for (const OutboxItem& item : items) {
    RejectItem(item, static_cast<int>(status.error_code()), status.error_message());
  }
  return Outcome::kOk;
}

Uploader::Outcome Uploader::SendSubmaps(const std::vector<OutboxItem>& items) {
  v1::UploadSubmapsRequest request;
  request.set_robot_id(registration_.robot_id());
  const std::vector<OutboxItem> sent =
      ParseBatch(items, request.mutable_submaps(), [this](const OutboxItem& item) {
    RejectItem(item, static_cast<int>(grpc::StatusCode::DATA_LOSS), "unreadable payload");
  });
  if (sent.empty()) return Outcome::kOk;
  grpc::ClientContext context;
  v1::UploadSubmapsResponse response;
  const grpc::Status status =
      Call(&context, [&] { return stub_->UploadSubmaps(&context, request, &response); });
  if (!status.ok()) return HandleCallFailure(status, sent);
  ApplyAcks(sent, response.acks());
  return Outcome::kOk;
}

Uploader::Outcome Uploader::SendDetections(const std::vector<OutboxItem>& items) {
  v1::ReportDetectionsRequest request;
  request.set_observer_id(registration_.robot_id());
  const std::vector<OutboxItem> sent =
      ParseBatch(items, request.mutable_detections(), [this](const OutboxItem& item) {
    RejectItem(item, static_cast<int>(grpc::StatusCode::DATA_LOSS), "unreadable payload");
  });
  if (sent.empty()) return Outcome::kOk;
  grpc::ClientContext context;
  v1::ReportDetectionsResponse response;
  const grpc::Status status =
      Call(&context, [&] { return stub_->ReportDetections(&context, request, &response); });
  if (!status.ok()) return HandleCallFailure(status, sent);
  ApplyAcks(sent, response.acks());
  return Outcome::kOk;
}

Uploader::Outcome Uploader::SendTrajectory(const OutboxItem& item) {
  v1::UploadTrajectoryRequest request;
  if (!request.ParseFromString(item.payload)) {
    RejectItem(item, static_cast<int>(grpc::StatusCode::DATA_LOSS), "unreadable payload");
    return Outcome::kOk;
  }
  grpc::ClientContext context;
  v1::UploadTrajectoryResponse response;
  const grpc::Status status =
      Call(&context, [&] { return stub_->UploadTrajectory(&context, request, &response); });
  if (!status.ok()) return HandleCallFailure(status, {item});
  Acknowledge({item}, response.duplicate() ? 1 : 0);
  return Outcome::kOk;
}

}  // namespace fleetmap
