#ifndef FLEETMAP_MAP_SERVER_SERVER_MAP_SERVICE_H_
#define FLEETMAP_MAP_SERVER_SERVER_MAP_SERVICE_H_

#include <functional>
#include <memory>

#include "map_server/server/conversions.h"
#include "map_server/server/density_relay.h"
#include "map_server/server/merge_worker.h"
#include "map_server/server/version_feed.h"
#include "map_server/store/map_store.h"
#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"

namespace fleetmap {

struct MapServiceOptions {
  UploadLimits limits;
  // Server clock (Unix seconds); tests substitute their own.
  std::function<double()> clock;
};

// The fleetmap.v1 handlers. Each one validates and converts (conversions.h), then hands the
// work to its owner: the MapStore commits uploads (acknowledged after commit), the MergeWorker
// renders, the VersionFeed serves published versions. No handler renders or blocks on the
// worker.
class MapServiceImpl final : public v1::MapService::Service {
 public:
  MapServiceImpl(const MapServiceOptions& options, MapStore* store, MergeWorker* worker,
                 VersionFeed* feed);

  grpc::Status RegisterRobot(grpc::ServerContext* context, const v1::RegisterRobotRequest* request,
                             v1::RegisterRobotResponse* response) override;
  grpc::Status UploadSubmaps(grpc::ServerContext* context, const v1::UploadSubmapsRequest* request,
                             v1::UploadSubmapsResponse* response) override;
  grpc::Status UploadTrajectory(grpc::ServerContext* context,
                                const v1::UploadTrajectoryRequest* request,
                                v1::UploadTrajectoryResponse* response) override;
  grpc::Status ReportDetections(grpc::ServerContext* context,
                                const v1::ReportDetectionsRequest* request,
                                v1::ReportDetectionsResponse* response) override;

  grpc::Status GetGlobalMap(grpc::ServerContext* context, const v1::GetGlobalMapRequest* request,
                            v1::GlobalMap* response) override;
  grpc::Status ListVersions(grpc::ServerContext* context, const v1::ListVersionsRequest* request,
                            v1::ListVersionsResponse* response) override;
  grpc::Status GetVersion(grpc::ServerContext* context, const v1::GetVersionRequest* request,
                          v1::VersionInfo* response) override;
  grpc::Status GetRobots(grpc::ServerContext* context, const v1::GetRobotsRequest* request,
                         v1::GetRobotsResponse* response) override;
  grpc::Status SubscribeMapUpdates(grpc::ServerContext* context,
                                   const v1::SubscribeMapUpdatesRequest* request,
                                   grpc::ServerWriter<v1::MapUpdate>* writer) override;
  // Collaborative localization (map_service_densities.cc).
  grpc::Status SendPoseDensity(grpc::ServerContext* context, const v1::PoseDensity* request,
                               v1::SendPoseDensityResponse* response) override;
  grpc::Status SubscribePoseDensities(grpc::ServerContext* context,
                                      const v1::SubscribePoseDensitiesRequest* request,
                                      grpc::ServerWriter<v1::PoseDensity>* writer) override;

 private:
  double Now() const { return options_.clock(); }
  // The version a query asks for (latest, by number or by time), with its cells.
  grpc::Status SelectVersion(const v1::GetGlobalMapRequest& request,
                             std::shared_ptr<const GlobalMapSnapshot>* snapshot);

  const MapServiceOptions options_;
  MapStore* const store_;
  MergeWorker* const worker_;
  VersionFeed* const feed_;
  DensityRelay densities_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_MAP_SERVICE_H_
