#include "map_server/server/map_server.h"

#include <chrono>

#include "map_server/store/memory_map_store.h"

namespace fleetmap {

std::unique_ptr<MapServer> MapServer::Start(const MapServerOptions& options, std::string* error) {
  std::unique_ptr<MapStore> store;
  if (options.db_path.empty()) {
    store = std::make_unique<MemoryMapStore>(options.retention);
  } else {
    SqliteMapStoreOptions store_options;
    store_options.path = options.db_path;
    store_options.fsync_every_commit = options.fsync_every_commit;
    store_options.retention = options.retention;
    store = SqliteMapStore::Open(store_options, error);
    if (!store) return nullptr;
  }
  return Start(options, std::move(store), error);
}

std::unique_ptr<MapServer> MapServer::Start(const MapServerOptions& options,
                                            std::unique_ptr<MapStore> store, std::string* error) {
  if (options.merge_worker != "engine" && options.merge_worker != "known-pose") {
    *error = "unknown merge worker '" + options.merge_worker + "' (engine, known-pose)";
    return nullptr;
  }
  std::unique_ptr<MapServer> server(new MapServer());
  server->store_ = std::move(store);
  if (options.merge_worker == "engine") {
    server->worker_ = std::make_unique<MergeEngineWorker>(
        MergeEngineWorkerOptions{options.merge, options.merge_engine, options.settle_seconds},
        server->store_.get(), &server->feed_);
  } else {
    server->worker_ = std::make_unique<KnownPoseMergeWorker>(options.merge, server->store_.get(),
                                                             &server->feed_);
  }
  server->worker_->Start();
  server->service_ = std::make_unique<MapServiceImpl>(options.service, server->store_.get(),
                                                      server->worker_.get(), &server->feed_);
  grpc::ServerBuilder builder;
  builder.AddListeningPort(options.listen, grpc::InsecureServerCredentials(), &server->port_);
  builder.SetMaxReceiveMessageSize(options.max_request_bytes);
  builder.SetMaxSendMessageSize(-1);
  builder.RegisterService(server->service_.get());
  server->server_ = builder.BuildAndStart();
  if (!server->server_ || server->port_ == 0) {
    *error = "cannot listen on " + options.listen + " (address in use or invalid?)";
    server->feed_.Close();
    server->worker_->Stop();
    server->server_.reset();
    server->shut_down_ = true;
    return nullptr;
  }
  server->host_ = options.listen.substr(0, options.listen.rfind(':'));
  return server;
}

MapServer::~MapServer() { Shutdown(); }

std::string MapServer::address() const { return host_ + ":" + std::to_string(port_); }

std::shared_ptr<grpc::Channel> MapServer::InProcessChannel() {
  return server_->InProcessChannel(grpc::ChannelArguments());
}

void MapServer::Shutdown(double grace_seconds) {
  if (shut_down_) return;
  shut_down_ = true;
  feed_.Close();
  const auto deadline = std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int>(grace_seconds * 1000));
  server_->Shutdown(deadline);
  server_->Wait();
  worker_->Stop();
}

std::shared_ptr<grpc::Channel> MakeClientChannel(const std::string& address) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(-1);
  arguments.SetMaxSendMessageSize(64 << 20);
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments);
}

}  // namespace fleetmap
