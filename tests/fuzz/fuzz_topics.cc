// libFuzzer harness: every topic's received-sample path. The first byte picks the topic and
// the options, the rest fills the generated C sample (fuzz_input.h); then what the readers
// and links run on a sample (common/transport/endpoint.cc, graph_feed.cc, dds_links.cc):
// conversion to the domain type (once), validation with the envelope, the links' own checks.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "common/rl/episode.h"
#include "common/rl/graph.h"
#include "common/rl/updates.h"
#include "common/transport/convert.h"
#include "common/transport/graph_feed.h"
#include "common/transport/validation.h"
#include "common/transport/wire.h"
#include "tests/fuzz/fuzz_input.h"

namespace srics::fuzz {
namespace {

using namespace srics::transport;

template <typename V, typename C>
void Visit(V& v, C& c);

// An IDL enum: 4 bytes on the wire, which Cyclone's deserializer refuses beyond the enum's
// largest value, so the sample carries one of its values (a C++ load of any other value of
// the C enum type is undefined behaviour: UBSan's -fsanitize=enum reports it).
template <typename V, typename E>
void VisitEnum(V& v, E& e, uint32_t largest) {
  static_assert(sizeof(E) == sizeof(uint32_t));
  uint32_t raw = 0;
  if constexpr (std::is_same_v<V, WireReader>) {
    v(raw);
    raw %= largest + 1;
    std::memcpy(&e, &raw, sizeof raw);
  } else {
    std::memcpy(&raw, &e, sizeof raw);
    v(raw);
  }
}

template <typename V>
void Visit(V& v, srics_Episode& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.actor_id);
  v(c.episode_id);
  VisitEnum(v, c.mode, srics_EPISODE_EVAL);
  v(c.policy_version);
  v(c.graph_version);
  v(c.num_entities);
  v(c.entity_dim);
  v(c.action_dim);
  v(c.num_steps);
  v(c.entity_kinds);
  v(c.states);
  v(c.actions);
  v(c.subgoal_entity);
  v(c.goal);
  v(c.ancestor_mask);
  v(c.subgoal_starts);
  v(c.subgoals);
  v(c.subgoal_tests);
}
template <typename V>
void Visit(V& v, srics_PolicyWeights& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.version);
  v(c.update_count);
  v(c.architecture);
  v(c.checksum);
  v(c.parameters);
}
template <typename V>
void Visit(V& v, srics_InteractionGraph& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.version);
  v(c.num_entities);
  v(c.mean_weights);
  v(c.adjacency);
  v(c.action_entity);
  v(c.threshold);
  v(c.ancestor_masks);
  v(c.depths);
  v(c.held_out_loss);
  v(c.training_updates);
  v(c.episodes_used);
}
template <typename V>
void Visit(V& v, srics_EvalResult& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.actor_id);
  v(c.policy_version);
  v(c.graph_version);
  v(c.env_steps);
  v(c.episodes);
  v(c.avg_distance);
  v(c.avg_object_distance);
  v(c.success_rate);
  v(c.entity_distance);
  v(c.subgoal_success);
  v(c.selectivity);
  v(c.independent_solved);
  v(c.independent_undone);
}
template <typename V>
void Visit(V& v, srics_LearnerStats& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.updates);
  v(c.transitions_inserted);
  v(c.training_env_steps);
  v(c.budget_env_steps);
  v(c.replay_size);
  v(c.episodes_accepted);
  v(c.episodes_rejected);
  v(c.policy_version);
  v(c.q_loss);
  v(c.policy_loss);
  v(c.alpha);
  v(c.entropy);
  v(c.updates_per_second);
  v(c.inserts_per_second);
  v(c.mean_reward);
}
template <typename V>
void Visit(V& v, srics_NodeStatus& c) {
  v(c.contract_version);
  v(c.run_id);
  v(c.role);
  v(c.node_id);
  v(c.host);
  v(c.pid);
  VisitEnum(v, c.state, srics_NODE_FAILED);
  v(c.policy_version);
  v(c.graph_version);
  v(c.env_steps);
  v(c.dropped_samples);
  v(c.uptime_ms);
  v(c.detail);
}

enum Topic : uint8_t { kEpisode, kWeights, kGraph, kEval, kStats, kStatus, kTopics };
constexpr char kRunId[] = "fuzz-run";

// What a reader of T runs (endpoint.cc: FromC, then Validate with the envelope against the
// run id); the sample if it passed.
template <typename T>
std::optional<T> Receive(WireReader& in, bool of_run) {
  typename internal::CType<T>::type sample{};
  Visit(in, sample);
  T out;
  internal::FromC(sample, &out);
  bool valid;
  if constexpr (std::is_same_v<T, rl::WeightsUpdate>)
    valid = Validate(out, internal::EnvelopeOf(sample), sample.checksum, of_run ? kRunId : "").ok();
  else
    valid = Validate(out, internal::EnvelopeOf(sample), of_run ? kRunId : "").ok();
  return valid ? std::optional<T>(std::move(out)) : std::nullopt;
}

void Run(const uint8_t* data, size_t size) {
  if (size < 1) return;
  const uint8_t head = data[0];
  const Topic topic = static_cast<Topic>((head & 0x0f) % kTopics);
  const bool of_run = head & 0x10, velocities = head & 0x20;
  WireReader in(data + 1, size - 1);
  switch (topic) {
    case kEpisode: {
      srics_Episode sample{};
      Visit(in, sample);
      if (!ValidateEnvelope(sample.contract_version, internal::RunIdOf(sample), of_run ? kRunId : "").ok()) return;
      rl::Episode episode;
      internal::FromC(sample, velocities, &episode);
      rl::EpisodeLimits limits;  // the defaults take every layout the contract allows
      limits.velocities = velocities;
      rl::ValidateEpisode(episode, limits);
      return;
    }
    case kWeights: Receive<rl::WeightsUpdate>(in, of_run); return;
    case kGraph: {
      std::optional<rl::GraphUpdate> g = Receive<rl::GraphUpdate>(in, of_run);
      if (!g) return;
      if (g->graph.num_entities > rl::kMaxGraphEntities) return;  // graph_feed.cc refuses it before computing
      AdoptComputedStructure(&*g);                                // a reason: graph.structure, refused by the feed
      return;
    }
    case kEval: Receive<rl::EvalReport>(in, of_run); return;
    case kStats: {
      const std::optional<rl::LearnerReport> r = Receive<rl::LearnerReport>(in, of_run);
      if (r) rl::ImplausibleProgress(r->progress(), 1000000);
      return;
    }
    case kStatus: Receive<rl::NodeStatus>(in, of_run); return;
    case kTopics: return;
  }
}

// Valid samples of each topic, written with WireWriter from what ToC makes of them.
template <typename C>
void Seed(const std::string& dir, const std::string& name, Topic topic, uint8_t flags, C& sample) {
  WireWriter w;
  w.Byte(static_cast<uint8_t>(topic | flags));
  Visit(w, sample);
  WriteSeed(dir, name, w.bytes());
}

template <typename T>
void SeedValue(const std::string& dir, const std::string& name, Topic topic, const T& value) {
  const Envelope envelope{kContractVersion, kRunId};
  typename internal::CType<T>::type sample;
  internal::SequenceBuffers buffers;
  internal::ToC(value, envelope, &sample, &buffers);
  Validation v;
  if constexpr (std::is_same_v<T, rl::WeightsUpdate>) {
    sample.checksum = ParameterChecksum(value.parameters);
    v = Validate(value, envelope, sample.checksum, kRunId);
  } else {
    v = Validate(value, envelope, kRunId);
  }
  if (!v.ok()) throw std::logic_error("seed " + name + ": " + v.reason);
  Seed(dir, name, topic, 0x10, sample);
}

void WriteSeeds(const std::string& dir) {
  {
    rl::Episode e;
    e.layout.num_entities = 2;
    e.layout.num_kinds = 2;
    e.layout.velocities = false;
    e.action_dim = 2;
    e.num_steps = 2;
    e.mode = rl::EpisodeMode::kTrain;
    e.entity_kinds = {0, 1};
    const int d = e.layout.entity_dim();
    for (int t = 0; t <= e.num_steps; ++t)
      for (int i = 0; i < 2; ++i)
        for (int k = 0; k < d; ++k) e.states.push_back(k < 2 ? (k == i ? 1.0f : 0.0f) : 0.1f * (t + i));
    e.actions = {0.5f, -0.5f, 0.25f, 0.0f};
    e.subgoal_entity = -1;
    e.goal = {0.1f, 0.1f, 0.2f, 0.2f};
    if (auto problem = rl::ValidateEpisode(e, rl::EpisodeLimits{}); !problem.empty())
      throw std::logic_error("seed episode: " + problem);
    srics_Episode sample;
    internal::ToC(e, Envelope{kContractVersion, kRunId}, &sample);
    Seed(dir, "episode", kEpisode, 0x10, sample);
  }
  {
    rl::WeightsUpdate w;
    w.version = 3;
    w.architecture = "mlp(4,8,2)";
    w.parameters = {0.5f, -0.25f, 1.0f, 0.0f, 3.0f};
    SeedValue(dir, "weights", kWeights, w);
  }
  {
    rl::GraphUpdate g;
    g.version = 2;
    g.graph = rl::InteractionGraph::Star(3);
    g.structure = rl::ComputeSubgoalStructure(g.graph);
    g.mean_weights.assign(9, 0.0);
    for (int j = 1; j < 3; ++j) g.mean_weights[j] = 0.5;
    g.threshold = 0.06;
    SeedValue(dir, "graph", kGraph, g);
  }
  {
    rl::EvalReport r;
    r.summary.episodes = 4;
    r.summary.avg_distance = 0.15f;
    r.summary.success_rate = 0.5f;
    r.summary.entity_distance = {0.1f, 0.2f};
    r.summary.subgoal_success = {1.0f, 0.5f};
    SeedValue(dir, "eval", kEval, r);
  }
  {
    rl::LearnerReport r;
    r.updates = 10;
    r.transitions_inserted = 100;
    r.training_env_steps = 100;
    r.budget_env_steps = 1000000;
    r.replay_size = 100;
    SeedValue(dir, "stats", kStats, r);
  }
  {
    rl::NodeStatus s;
    s.role = "actor";
    s.host = "host";
    s.report.detail = "ok | rejected: graph.entities=1";
    SeedValue(dir, "status", kStatus, s);
  }
}

}  // namespace
}  // namespace srics::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = srics::fuzz::SeedDir()) {
    srics::fuzz::WriteSeeds(dir);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  srics::fuzz::Run(data, size);
  return 0;
}
