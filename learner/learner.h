#pragma once
// The learning core shared by the learner process and the in-process trainer: validates and
// stores episodes, tracks the interaction graph, keeps the update-to-data ratio, runs SAC
// updates and checkpoints everything. No DDS, no YAML: it takes plain structs.

#include <cstdint>
#include <memory>
#include <string>

#include "common/config/config.h"
#include "common/files/durable_file.h"
#include "common/rl/agent_shape.h"
#include "common/rl/episode.h"
#include "common/rl/graph.h"
#include "common/rl/rate_limiter.h"
#include "learner/hac.h"
#include "learner/relabeler.h"
#include "learner/replay_buffer.h"
#include "learner/sac.h"

namespace srics::learner {

// What the learning core needs, built from a run's config by LearnerOptionsFor.
struct LearnerOptions {
  config::Method method = config::Method::kSrics;
  config::AgentConfig agent;
  config::LearnerConfig learner;
  AgentShape shape;          // network sizes (rl::RunShape::agent)
  rl::EpisodeLimits limits;  // what an episode of this run looks like (rl::RunShape::limits)
  GoalRegion goal_region;    // where relabeled goals are sampled
  uint64_t run_seed = 1;
  uint64_t total_env_steps = 0;  // the run's budget of training env steps
  // HAC only: its settings and the high level's network sizes (`shape` is the low level's)
  HacOptions hac;
  AgentShape high_shape;
  int max_entities = 0;  // of the run's environment (HAC's replays pad to it)
};

LearnerOptions LearnerOptionsFor(const config::Config& config, const rl::RunShape& shape);

class Learner {
 public:
  explicit Learner(const LearnerOptions& options);

  // Validates and stores a training or exploration episode. Returns "" when accepted, else
  // why it was rejected (the replay is unchanged then and the rejection is counted).
  // Exploration episodes are accepted but not stored when learner.exploration_into_replay is
  // false (counted in exploration_skipped(); they count for nothing then).
  // Once the run's budget is in (BudgetReached), further episodes are not stored: the learner
  // trains on the budget's data, and actors still running until they hear of the end are
  // counted in episodes_beyond_budget() (not rejected).
  std::string Ingest(rl::Episode episode);

  // Uses a new interaction graph for rewards and subgoal choice. Methods that use the graph
  // do no updates before the first one arrives.
  void SetGraph(const rl::SubgoalStructure& structure);
  // The run's catalogue graph; each episode's ancestor sets are derived from its entity kinds.
  void SetGraph(const rl::InteractionGraph& catalogue);
  bool has_graph() const { return has_graph_; }
  // The object attempted together with the episode's subgoal entity (a tied pair,
  // graph.object_ties: joint), -1 for none.
  int SubgoalPartnerOf(const rl::Episode& episode) { return relabeler_.PartnerOf(episode); }

  // True when the rate limiter allows one more update now.
  bool CanUpdate() const;
  // One SAC update on a freshly relabeled batch. Precondition: CanUpdate(). An update that met
  // a non-finite value changed no network from that point (SacAgent::Update); it still counts
  // as an update for the rate limiter and is counted in non_finite_updates().
  UpdateStats Update();
  // Updates the limiter allows right now.
  uint64_t UpdatesAllowed() const;
  // Updates the rate limit owes the data it counts (ratio x counted transitions - updates; 0
  // while blocked): what actors hold back by (LearnerStats.update_backlog).
  double UpdateBacklog() const;

  // Publishing: the flat policy weights with a new version number (HAC: the high level's
  // parameters, then the low level's) and their architecture signature.
  std::vector<float> TakePolicyWeights();
  std::string PolicySignature();
  bool PublishDue() const;

  // Raises the next policy version by `count` (after a restart from a checkpoint).
  void SkipPolicyVersions(uint64_t count) { counters_.policy_version += count; }

  // Everything a resumed run needs to go on as if uninterrupted, in one file written
  // atomically: networks, optimizers, temperature, counters, the replay (every stored episode
  // and its insert counters), the rate limiter's state and the random streams of sampling and
  // updates.
  // `keep` > 1 keeps that many generations (path the newest, path.1 the one before, ...).
  // Throws nn::CheckpointError when the file cannot be written (the previous checkpoint is
  // then kept as it was, and no temporary file is left).
  void SaveCheckpoint(const std::string& path, int keep = 1, files::FileSystem& fs = files::FileSystem::Posix());
  // Restores what SaveCheckpoint wrote. A checkpoint of the format before the replay was saved
  // (nn format version 1) restores networks and counters with an empty replay (the warm-up
  // then refills it). Throws nn::CheckpointError (cannot open, truncated, corrupted, another
  // architecture, a replay that does not fit this run's environment); nothing is changed then
  // unless the optimizer state itself is malformed.
  void LoadCheckpoint(const std::string& path);
  // False after loading a checkpoint that had no replay (the old format).
  bool replay_restored() const { return replay_restored_; }

  const LearnerCounters& counters() const { return counters_; }
  // True once the run's budget of training env steps is in (run.total_env_steps).
  bool BudgetReached() const { return counters_.training_env_steps >= options_.total_env_steps; }
  uint64_t episodes_rejected() const { return rejected_; }
  uint64_t non_finite_updates() const { return non_finite_updates_; }
  // Non-finite updates since the last finite one: a long run of them means learning stopped
  // (LearnerLoop ends the run at learner.max_skipped_updates_in_a_row).
  uint64_t non_finite_in_a_row() const { return non_finite_in_a_row_; }
  uint64_t episodes_beyond_budget() const { return beyond_budget_; }
  // Exploration episodes not stored (learner.exploration_into_replay: false).
  uint64_t exploration_skipped() const { return exploration_skipped_; }
  const ReplayBuffer& replay() const { return replay_; }
  // The batch of the last Update (not HAC's; benchmarks time the agent's update on it).
  const TrainingBatch& last_batch() const { return batch_; }
  // The agent that acts (HAC: the low level).
  SacAgent& agent() { return agent_; }
  // HAC's levels (the high level and both transition replays); null for other methods.
  HacLevels* hac() { return hac_.get(); }
  const HacLevels* hac() const { return hac_.get(); }
  const AgentShape& shape() const { return shape_; }
  // What learner.precision asked for the update's products, and what runs (bf16 asked on a
  // CPU without it runs fp32).
  bool bf16_requested() const { return options_.learner.precision == config::ProductPrecision::kBf16; }
  nn::GemmPrecision product_precision() const { return agent_.product_precision(); }

 private:
  LearnerOptions options_;
  AgentShape shape_;
  ReplayBuffer replay_;
  Relabeler relabeler_;
  SacAgent agent_;
  std::unique_ptr<HacLevels> hac_;
  rl::RateLimiter limiter_;
  TrainingBatch batch_;
  LearnerCounters counters_;
  uint64_t rejected_ = 0;
  uint64_t non_finite_updates_ = 0;
  uint64_t non_finite_in_a_row_ = 0;
  uint64_t beyond_budget_ = 0;
  uint64_t exploration_skipped_ = 0;
  bool has_graph_ = false;
  // Updates are blocked until there is a graph (if the method needs one) and the replay
  // holds warmup_steps transitions (also after a restart, when it starts empty). While
  // blocked, the limiter's count of inserted transitions is shifted so that no allowance of
  // updates piles up; when unblocked, updates follow the ratio from there.
  bool Blocked() const;
  uint64_t LimiterInserted() const { return counters_.transitions_inserted - limiter_offset_; }
  uint64_t limiter_offset_ = 0;
  uint64_t published_at_update_ = 0;
  bool published_once_ = false;
  bool replay_restored_ = false;
};

}  // namespace srics::learner
