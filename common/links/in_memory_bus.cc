#include "common/links/in_memory_bus.h"

#include <algorithm>
#include <exception>
#include <stdexcept>

namespace srics::links {
namespace {

// The bus's latest value of a keep-last-1 topic if this reader has not seen its version yet
// (then marked seen): readers get the newest sample once, as over DDS.
template <typename T>
std::optional<T> Unseen(const std::optional<T>& latest, uint64_t* seen_version) {
  if (!latest || latest->version <= *seen_version) return std::nullopt;
  *seen_version = latest->version;
  return latest;
}

}  // namespace

class InMemoryBus::Actor : public ActorLink {
 public:
  Actor(InMemoryBus* bus, uint32_t id) : bus_(bus), id_(id), outbox_(bus->OutboxFor(1 + uint64_t{id})) {}

  // each publication once (as a DDS take), and only above the caller's version
  std::optional<rl::WeightsUpdate> PollWeights(uint64_t newer_than) override {
    if (!bus_->weights_ || bus_->weights_->version <= std::max(newer_than, weights_seen_)) return std::nullopt;
    weights_seen_ = bus_->weights_->version;
    return bus_->weights_;
  }
  std::optional<rl::GraphUpdate> PollGraph() override { return Unseen(bus_->graph_, &graph_seen_); }
  // No waiting: in one thread nothing can arrive while we wait.
  std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds) override { return bus_->progress_; }
  bool PublishEpisode(const rl::Episode& episode) override {
    bus_->Deliver(outbox_, [bus = bus_, episode]() mutable {  // one copy, as before the outboxes
      ++bus->episodes_published_;
      if (GraphServiceWants(episode.mode, bus->graph_takes_training_) && bus->graph_source_attached_)
        bus->graph_queue_.push_back(episode);
      bus->learner_queue_.push_back(std::move(episode));
    });
    return true;
  }
  void PublishEval(const rl::EvalReport& report) override {
    bus_->Deliver(outbox_, [bus = bus_, report] {
      if (bus->observer_) bus->observer_->OnEval(report);
    });
  }
  void PublishStatus(const rl::NodeReport& report) override { bus_->DeliverStatus(outbox_, "actor", id_, report); }

 private:
  InMemoryBus* bus_;
  uint32_t id_;
  Outbox* outbox_;
  uint64_t weights_seen_ = 0, graph_seen_ = 0;
};

class InMemoryBus::Learner : public LearnerLink {
 public:
  explicit Learner(InMemoryBus* bus) : bus_(bus), outbox_(bus->OutboxFor(kLearnerOrder)) {}

  size_t TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds) override {
    size_t taken = 0;
    for (; taken < max && !bus_->learner_queue_.empty(); ++taken) {
      out->push_back(std::move(bus_->learner_queue_.front()));
      bus_->learner_queue_.pop_front();
    }
    return taken;
  }
  std::optional<rl::GraphUpdate> PollGraph() override { return Unseen(bus_->graph_, &graph_seen_); }
  void PublishWeights(rl::WeightsUpdate weights) override {
    // held, the weights wait in a shared slot (a std::function must be copyable): no copy of
    // the parameters either way
    auto slot = std::make_shared<rl::WeightsUpdate>(std::move(weights));
    bus_->Deliver(outbox_, [bus = bus_, slot] {
      bus->weights_ = std::move(*slot);
      if (bus->observer_) bus->observer_->OnWeights(*bus->weights_);
    });
  }
  void PublishStats(const rl::LearnerReport& report) override {
    bus_->Deliver(outbox_, [bus = bus_, report] {
      bus->progress_ = report.progress();
      if (bus->observer_) bus->observer_->OnLearnerStats(report);
    });
  }
  void PublishStatus(const rl::NodeReport& report) override { bus_->DeliverStatus(outbox_, "learner", 0, report); }

 private:
  InMemoryBus* bus_;
  Outbox* outbox_;
  uint64_t graph_seen_ = 0;
};

class InMemoryBus::Source : public EpisodeSource {
 public:
  explicit Source(InMemoryBus* bus) : bus_(bus) {}
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    for (auto& e : bus_->graph_queue_) out->push_back(std::move(e));
    bus_->graph_queue_.clear();
    return true;
  }

 private:
  InMemoryBus* bus_;
};

class InMemoryBus::Sink : public GraphSink {
 public:
  explicit Sink(InMemoryBus* bus) : bus_(bus), outbox_(bus->OutboxFor(kGraphOrder)) {}
  void Publish(const rl::GraphUpdate& graph) override {
    // the version rule is checked at once, so the service sees its own error (the graph service
    // steps while the bus is not held: InProcessRun)
    bus_->CheckGraphVersion(graph);
    bus_->Deliver(outbox_, [bus = bus_, graph] { bus->PublishGraph(graph); });
  }
  void PublishStatus(const rl::NodeReport& report) override { bus_->DeliverStatus(outbox_, "graph", 0, report); }

 private:
  InMemoryBus* bus_;
  Outbox* outbox_;
};

std::unique_ptr<ActorLink> InMemoryBus::ActorEnd(uint32_t actor_id) { return std::make_unique<Actor>(this, actor_id); }

std::unique_ptr<LearnerLink> InMemoryBus::LearnerEnd() { return std::make_unique<Learner>(this); }

std::unique_ptr<EpisodeSource> InMemoryBus::GraphSourceEnd(bool training_episodes) {
  if (graph_source_attached_) throw std::logic_error("InMemoryBus: one graph service per bus");
  graph_source_attached_ = true;
  graph_takes_training_ = training_episodes;
  return std::make_unique<Source>(this);
}

std::unique_ptr<GraphSink> InMemoryBus::GraphSinkEnd() { return std::make_unique<Sink>(this); }

void InMemoryBus::Deliver(Outbox* outbox, std::function<void()> publication) {
  if (held_)
    outbox->push_back(std::move(publication));
  else
    publication();
}

void InMemoryBus::DeliverStatus(Outbox* outbox, std::string role, uint32_t node_id, const rl::NodeReport& report) {
  Deliver(outbox, [this, role = std::move(role), node_id, report] {
    if (observer_) observer_->OnStatus(role, node_id, report);
  });
}

void InMemoryBus::Hold() { held_ = true; }

void InMemoryBus::Release() {
  held_ = false;
  // every outbox is emptied and every publication tried, even after one threw (a monitor's CSV
  // on a full disk): none is delivered twice or lost silently; the first error is rethrown
  std::exception_ptr first_error;
  for (auto& [order, outbox] : outboxes_) {
    Outbox due;
    due.swap(outbox);
    for (auto& publication : due) {
      try {
        publication();
      } catch (...) {
        if (!first_error) first_error = std::current_exception();
      }
    }
  }
  if (first_error) std::rethrow_exception(first_error);
}

void InMemoryBus::CheckGraphVersion(const rl::GraphUpdate& graph) const {
  if (graph_ && graph.version <= graph_->version)
    throw std::invalid_argument("InMemoryBus: graph versions must increase");
}

void InMemoryBus::PublishGraph(const rl::GraphUpdate& graph) {
  CheckGraphVersion(graph);
  graph_ = graph;
  if (observer_) observer_->OnGraph(graph);
}

}  // namespace srics::links
