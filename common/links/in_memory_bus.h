#pragma once
// The in-memory bus: the links of every role in one process, with the delivery rules of the
// DDS topics (common/transport/topics.h) but no network and no threads. Episodes reach the
// learner (all) and the graph service (explore ones) in the order they were published;
// weights, graph and learner stats are "latest value" topics (keep-last 1, transient-local):
// each reader gets the newest one it has not seen. An Observer sees what a monitor would.
// `srics run --in-process` wires the same loops as the distributed run with it.
//
//   InMemoryBus bus;
//   auto learner_link = bus.LearnerEnd();
//   auto actor_link = bus.ActorEnd(0);
//   ActorLoop actor(options, actor_link.get());
//
// Threading: each end is used from one thread, and the bus must outlive its ends. Ends may be
// stepped on different threads only between Hold() and Release() (both called from the thread
// that owns the bus, while no end is in use): in between, every publication waits in its end's
// outbox, so the state the ends read does not change; Release() delivers the outboxes in a fixed
// order (graph service, actors by id, learner), so two threads give the same run every time.

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/links/links.h"

namespace srics::links {

// What a monitor on the bus sees (every publication, in order).
class BusObserver {
 public:
  virtual ~BusObserver() = default;
  virtual void OnEval(const rl::EvalReport& report) { (void)report; }
  virtual void OnLearnerStats(const rl::LearnerReport& report) { (void)report; }
  virtual void OnGraph(const rl::GraphUpdate& graph) { (void)graph; }
  virtual void OnWeights(const rl::WeightsUpdate& weights) { (void)weights; }
  virtual void OnStatus(const std::string& role, uint32_t id, const rl::NodeReport& report) {
    (void)role, (void)id, (void)report;
  }
};

class InMemoryBus {
 public:
  explicit InMemoryBus(BusObserver* observer = nullptr) : observer_(observer) {}
  InMemoryBus(const InMemoryBus&) = delete;
  InMemoryBus& operator=(const InMemoryBus&) = delete;

  std::unique_ptr<ActorLink> ActorEnd(uint32_t actor_id);
  std::unique_ptr<LearnerLink> LearnerEnd();
  // The graph service's two ends (one service per bus). Its source gets the explore episodes,
  // and the training episodes too with `training_episodes` (graph.refine_after_publish).
  std::unique_ptr<EpisodeSource> GraphSourceEnd(bool training_episodes = false);
  std::unique_ptr<GraphSink> GraphSinkEnd();
  // Injects a graph as the graph service would publish it (a run with a given graph).
  void PublishGraph(const rl::GraphUpdate& graph);

  // Publications wait in their ends' outboxes from Hold() to Release(), which delivers them
  // (every one, then rethrows the first error a delivery threw).
  void Hold();
  void Release();
  bool held() const { return held_; }

  // Counters for tests and summaries.
  uint64_t episodes_published() const { return episodes_published_; }
  uint64_t episodes_pending_learner() const { return learner_queue_.size(); }

 private:
  class Actor;
  class Learner;
  class Source;
  class Sink;

  // Throws std::invalid_argument unless `graph` is newer than the bus's graph.
  void CheckGraphVersion(const rl::GraphUpdate& graph) const;
  // A publication: applied now, or queued in its end's outbox while the bus is held.
  using Outbox = std::vector<std::function<void()>>;
  void Deliver(Outbox* outbox, std::function<void()> publication);
  // A node's status, delivered as Deliver does, to the observer (if any).
  void DeliverStatus(Outbox* outbox, std::string role, uint32_t node_id, const rl::NodeReport& report);
  // Delivery order of the outboxes: the graph service's (0), actor k's (1 + k), the learner's.
  static constexpr uint64_t kGraphOrder = 0, kLearnerOrder = UINT64_MAX;
  Outbox* OutboxFor(uint64_t order) { return &outboxes_[order]; }

  BusObserver* observer_;
  bool held_ = false;
  std::map<uint64_t, Outbox> outboxes_;  // nodes stay put: each end keeps a pointer to its own
  std::deque<rl::Episode> learner_queue_;
  std::deque<rl::Episode> graph_queue_;
  bool graph_source_attached_ = false;
  bool graph_takes_training_ = false;
  std::optional<rl::WeightsUpdate> weights_;
  std::optional<rl::GraphUpdate> graph_;
  std::optional<rl::LearnerProgress> progress_;
  uint64_t episodes_published_ = 0;
};

}  // namespace srics::links
