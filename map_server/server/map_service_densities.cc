// MapServiceImpl: the collaborative-localization relay (SendPoseDensity, SubscribePoseDensities).
#include <chrono>
#include <cmath>

#include "map_server/server/conversions.h"
#include "map_server/server/map_service.h"

namespace fleetmap {
namespace {

using grpc::Status;
using grpc::StatusCode;

constexpr int kMaxKernels = 256;
constexpr char kDensitySubscribedKey[] = "fleetmap-density-subscribed";

Status Invalid(const std::string& message) { return Status(StatusCode::INVALID_ARGUMENT, message); }

Status CheckKernel(const v1::PoseDensityKernel& k, int index) {
  const std::string where = "kernels[" + std::to_string(index) + "]: ";
  for (double value :
       {k.weight(), k.x(), k.y(), k.var_x(), k.cov_xy(), k.var_y(), k.theta(), k.var_theta()}) {
    if (!std::isfinite(value)) return Invalid(where + "not a finite number");
  }
  if (!(k.weight() > 0.0)) return Invalid(where + "weight must be > 0");
  if (!(k.var_x() > 0.0 && k.var_y() > 0.0 && k.var_x() * k.var_y() > k.cov_xy() * k.cov_xy())) {
    return Invalid(where + "position covariance must be positive definite");
  }
  if (k.var_theta() < 0.0) return Invalid(where + "var_theta must be >= 0");
  return Status::OK;
}

}  // namespace

Status MapServiceImpl::SendPoseDensity(grpc::ServerContext* /*context*/,
                                       const v1::PoseDensity* request,
                                       v1::SendPoseDensityResponse* response) {
  Status status = ValidateRobotId(request->observer_id(), "observer_id");
  if (status.ok()) status = ValidateRobotId(request->observed_id(), "observed_id");
  if (!status.ok()) return status;
  if (request->observer_id() == request->observed_id()) {
    return Invalid("observer_id and observed_id are the same robot");
  }
  if (!std::isfinite(request->timestamp())) return Invalid("timestamp is not finite");
  if (request->kernels_size() < 1 || request->kernels_size() > kMaxKernels) {
    return Invalid("a density needs 1-" + std::to_string(kMaxKernels) + " kernels, got " +
                   std::to_string(request->kernels_size()));
  }
  for (int i = 0; i < request->kernels_size(); ++i) {
    status = CheckKernel(request->kernels(i), i);
    if (!status.ok()) return status;
  }
  for (const std::string& id : {request->observer_id(), request->observed_id()}) {
    if (!store_->GetRobot(id)) {
      return Status(StatusCode::NOT_FOUND,
                    "unknown robot \"" + id + "\": call RegisterRobot first");
    }
  }
  response->set_receivers(densities_.Publish(*request));
  return Status::OK;
}

Status MapServiceImpl::SubscribePoseDensities(grpc::ServerContext* context,
                                              const v1::SubscribePoseDensitiesRequest* request,
                                              grpc::ServerWriter<v1::PoseDensity>* writer) {
  Status status = ValidateRobotId(request->robot_id(), "robot_id");
  if (!status.ok()) return status;
  if (!store_->GetRobot(request->robot_id())) {
    return Status(StatusCode::NOT_FOUND,
                  "unknown robot \"" + request->robot_id() + "\": call RegisterRobot first");
  }
  const auto subscription = densities_.Subscribe(request->robot_id());
  // Tells the robot at once that it is listening (a stream otherwise says nothing until the
  // first density).
  context->AddInitialMetadata(kDensitySubscribedKey, "1");
  writer->SendInitialMetadata();
  // Wake up regularly to notice a cancelled client or a stopping server.
  while (!context->IsCancelled() && !feed_->closed()) {
    const std::optional<v1::PoseDensity> density =
        subscription->Pop(std::chrono::milliseconds(200));
    if (density && !writer->Write(*density)) break;  // the client went away
  }
  densities_.Unsubscribe(request->robot_id(), subscription);
  return Status::OK;
}

}  // namespace fleetmap
