// MergeEngine: the global searches of an update (each new submap over the whole map of every
// other part) run ahead, side by side. ProcessCrossMatches then takes each answer only for the
// same submap over the same map (a join earlier in the same update changes the joined part's
// map, and a search over it runs again), so the answers are those of running them one by one.

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"
#include "shared/core/thread_pool.h"

namespace fleetmap {

MergeEngine::GlobalSearch MergeEngine::PrepareGlobalSearch(const std::string& robot, int64_t submap,
                                                           const MatchTarget& target) {
  GlobalSearch search;
  search.source = SubmapSource(robot, submap);
  search.centroid = Centroid(search.source.coarse);
  TransformSource(Rigid2d(-search.centroid, 0.0), &search.source);
  search.window = target.Everywhere();
  return search;
}

std::map<MergeEngine::CrossKey, MergeEngine::SearchedAhead> MergeEngine::SearchCrossMatchesAhead() {
  struct Planned {
    CrossKey key;
    const MatchTarget* target = nullptr;
    GlobalSearch search;
    MatchResult result;
  };
  // The same walk as ProcessCrossMatches, changing nothing.
  std::vector<Planned> planned;
  int budget = options_.max_global_searches_per_update;
  const std::map<std::string, int> never_tried;
  for (const auto& [robot_id, robot] : robots_) {
    for (int64_t id : robot->cross_queue) {
      if (!graph_.HasNode({robot_id, id})) continue;
      const std::set<std::string> roots = OtherRoots(robot_id);
      const auto tried = robot->cross_tried.find(id);
      for (const std::string& root : roots) {
        if (!CrossSearchDue(tried == robot->cross_tried.end() ? never_tried : tried->second, root))
          continue;
        if (budget-- <= 0) break;
        planned.push_back({{robot_id, id, root, ""}, nullptr, {}, {}});
      }
      if (budget < 0) break;
    }
    if (budget < 0) break;
  }
  // The targets are cached per part and would be built by ProcessCrossMatches anyway.
  std::vector<Planned*> runnable;
  for (Planned& p : planned) {
    auto& [robot_id, id, root, stamp] = p.key;
    const MatchTarget& target = Target(root);
    if (target.empty()) continue;
    stamp = CanvasStamp(root);
    p.target = &target;
    p.search = PrepareGlobalSearch(robot_id, id, target);
    runnable.push_back(&p);
  }
  search_pool_->ParallelFor(runnable.size(), [&](size_t i) {
    Planned& p = *runnable[i];
    p.result = p.target->Match(p.search.source, p.search.window, options_.cross_gates);
  });
  std::map<CrossKey, SearchedAhead> ahead;
  for (const Planned* p : runnable) {
    ahead[p->key] = {p->search.centroid, p->result};
  }
  return ahead;
}

}  // namespace fleetmap
