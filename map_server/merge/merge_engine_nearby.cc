// MergeEngine: new submaps searched for around their graph poses (local constraints against
// the other joined robots' maps, loop closures against the robot's own older submaps). The
// searches do not depend on each other, so they run side by side; their edges go into the graph
// in the order they were planned, so the result does not depend on the thread count.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"
#include "shared/core/thread_pool.h"

namespace fleetmap {

void MergeEngine::PlanLocalConstraints(std::vector<NearbySearch>* searches) {
  if (!options_.local_constraints) return;
  int budget = options_.max_local_searches_per_update;
  for (auto& [robot_id, robot] : robots_) {
    const std::string root = Root(robot_id);
    if (Members(root).size() < 2) continue;  // nobody else to match against yet
    for (int64_t id : std::vector<int64_t>(robot->local_queue.begin(), robot->local_queue.end())) {
      const auto pose = graph_.NodePose({robot_id, id});
      if (!pose) continue;
      if (budget-- <= 0) return;
      robot->local_queue.erase(id);
      const auto bounds = robot->SubmapBounds(id, *pose);
      if (!bounds) continue;
      NearbySearch search;
      search.kind = EdgeKind::kCrossMatch;
      search.submap = {robot_id, id};
      search.make_target = [this, root, robot = robot_id, box = Grow(*bounds, 1.0)] {
        return CroppedTarget(root, robot, box);
      };
      search.source = &SubmapSource(robot_id, id);
      search.window.center = *pose;
      search.window.linear_half_extent = options_.local_window;
      search.window.angular_half_extent = options_.local_angular_window;
      searches->push_back(std::move(search));
    }
  }
}

void MergeEngine::ProcessNearbyMatches(MergeUpdate* update) {
  std::vector<NearbySearch> searches;
  PlanLocalConstraints(&searches);
  PlanLoopClosures(&searches);
  // The searches only read canvases, submaps, sources and graph poses, which nothing changes
  // until they are all done.
  search_pool_->ParallelFor(searches.size(), [&](size_t i) {
    NearbySearch& search = searches[i];
    const std::unique_ptr<MatchTarget> target = search.make_target();
    if (!target->empty())
      search.result = target->Match(*search.source, search.window, options_.verify_gates);
  });

  std::vector<const NearbySearch*> matched;
  std::vector<EdgeToRefine> edges;
  for (const NearbySearch& search : searches) {
    if (!search.result.accepted) continue;
    std::optional<NodeId> from = search.from;
    if (search.kind == EdgeKind::kCrossMatch) {
      from = NearestNode(Root(search.submap.robot), search.submap.robot,
                         search.result.pose.translation());
      // The match that joined this submap may already tie it to that node: the same
      // measurement twice would weigh as two.
      if (!from || HasMatchEdge(*from, search.submap)) continue;
    }
    matched.push_back(&search);
    edges.push_back(PrepareMatchedEdge(*from, search.submap, search.result.pose, search.kind));
  }
  std::vector<RelativeEdge> refined(edges.size());
  search_pool_->ParallelFor(edges.size(),
                            [&](size_t i) { refined[i] = RefineMatchedEdge(edges[i]); });

  for (size_t i = 0; i < refined.size(); ++i) {
    const NearbySearch& search = *matched[i];
    const MatchResult& r = search.result;
    graph_.AddEdge(refined[i]);
    graph_dirty_ = true;
    AlignmentEvent event;
    event.type = AlignmentEventType::kConstraintAdded;
    event.robot_a = refined[i].from.robot;
    event.robot_b = search.submap.robot;
    event.submaps_b = {search.submap.submap};
    if (search.kind == EdgeKind::kCrossMatch) {
      event.evidence = EvidenceKind::kCrossMatch;
      FillEvent(r, &event);
    } else {
      event.evidence = EvidenceKind::kLoopClosure;
      event.score = r.score;
      event.overlap = r.overlap;
      event.residual = r.residual;
      event.reason =
          "loop closure with submap " + std::to_string(refined[i].from.submap) + ": " + r.reason;
    }
    update->events.push_back(event);
  }
}

}  // namespace fleetmap
