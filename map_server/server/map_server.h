#ifndef FLEETMAP_MAP_SERVER_SERVER_MAP_SERVER_H_
#define FLEETMAP_MAP_SERVER_SERVER_MAP_SERVER_H_

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "map_server/server/known_pose_merge_worker.h"
#include "map_server/server/merge_engine_worker.h"
#include "map_server/server/map_service.h"
#include "map_server/server/version_feed.h"
#include "map_server/store/map_store.h"
#include "map_server/store/sqlite_map_store.h"

namespace fleetmap {

struct MapServerOptions {
  std::string db_path;  // SQLite database; empty = in memory (tests)
  std::string listen = "127.0.0.1:50051";  // host:port; port 0 picks a free one
  bool fsync_every_commit = false;
  RetentionOptions retention;
  MergeWorkerOptions merge;  // queue, version pacing, resolution: both workers
  // "engine": MergeEngineWorker (robots of unknown start are aligned; robots registered with a
  // start pose are held there); "known-pose": KnownPoseMergeWorker (registered poses only).
  std::string merge_worker = "engine";
  MergeEngineOptions merge_engine;
  // The engine worker's rebuild once uploads settle (MergeEngineWorkerOptions::settle_seconds).
  double settle_seconds = MergeEngineWorkerOptions().settle_seconds;
  MapServiceOptions service;
  // Requests larger than this are refused by gRPC with RESOURCE_EXHAUSTED.
  int max_request_bytes = 64 << 20;
};

// The whole server: store, merge worker, version feed, gRPC service, wired together and
// started. Used by fleetmap-server, the tests and the benchmark.
class MapServer {
 public:
  // Opens the store and starts serving; nullptr with `error` on failure (bad database, port in
  // use, ...).
  static std::unique_ptr<MapServer> Start(const MapServerOptions& options, std::string* error);
  // The same with a given store (e.g. a MemoryMapStore).
  static std::unique_ptr<MapServer> Start(const MapServerOptions& options,
                                          std::unique_ptr<MapStore> store, std::string* error);
  ~MapServer();

  int port() const { return port_; }
  std::string address() const;
  // A channel to this server that bypasses the network.
  std::shared_ptr<grpc::Channel> InProcessChannel();
  MapStore* store() { return store_.get(); }
  // Stops subscriptions, drains RPCs (up to `grace_seconds`), then the worker; idempotent.
  void Shutdown(double grace_seconds = 2.0);

 private:
  MapServer() = default;

  std::unique_ptr<MapStore> store_;
  VersionFeed feed_;
  std::unique_ptr<MergeWorker> worker_;
  std::unique_ptr<MapServiceImpl> service_;
  std::unique_ptr<grpc::Server> server_;
  std::string host_;
  int port_ = 0;
  bool shut_down_ = false;
};

// A client channel with limits that fit whole global maps.
std::shared_ptr<grpc::Channel> MakeClientChannel(const std::string& address);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_MAP_SERVER_H_
