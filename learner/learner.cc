#include "learner/learner.h"

#include "common/rl/agent_shape.h"
#include "common/rl/seeds.h"

namespace srics::learner {

LearnerOptions LearnerOptionsFor(const config::Config& config) {
  LearnerOptions o;
  o.method = config.run.method;
  o.agent = config.agent;
  o.learner = config.learner;
  o.shape = rl::AgentShapeFor(config.env, config.run.method);
  o.limits = rl::EpisodeLimitsFor(config.env);
  const auto& sampling = config.env.sampling;
  o.goal_region = {sampling.subgoal_low[0], sampling.subgoal_high[0], sampling.subgoal_low[1], sampling.subgoal_high[1]};
  o.run_seed = config.run.seed;
  o.total_env_steps = config.run.total_env_steps;
  return o;
}

Learner::Learner(const LearnerOptions& options)
    : options_(options),
      shape_(options.shape),
      replay_(options.learner.replay_capacity),
      relabeler_(options.method, options.agent.reward, options.learner.relabel, options.goal_region,
                 rl::DeriveSeed(options.run_seed, rl::SeedPurpose::kLearnerReplay)),
      agent_(shape_, options.agent, rl::DeriveSeed(options.run_seed, rl::SeedPurpose::kLearnerAgent)),
      limiter_(options.learner.updates_per_step, options.learner.warmup_steps, options.learner.rate_error_buffer) {}

std::string Learner::Ingest(rl::Episode episode) {
  std::string problem = rl::ValidateEpisode(episode, options_.limits);
  if (problem.empty() && episode.layout.entity_dim() != shape_.entity_dim)
    problem = "entity tokens of " + std::to_string(episode.layout.entity_dim()) +
              " floats, the networks take " + std::to_string(shape_.entity_dim);
  if (problem.empty() && relabeler_.full_goal() && episode.mode == rl::EpisodeMode::kTrain &&
      episode.goal.size() != static_cast<size_t>(2 * episode.layout.num_entities))
    problem = "SAC+HER training episodes need a full goal";
  if (problem.empty() && episode.mode == rl::EpisodeMode::kEval) problem = "evaluation episodes are not training data";
  if (!problem.empty()) {
    ++rejected_;
    return problem;
  }
  if (BudgetReached()) {
    ++beyond_budget_;
    return "";
  }
  counters_.transitions_inserted += episode.num_steps;
  if (!rl::UsesGraph(options_.method) || has_graph_) counters_.training_env_steps += episode.num_steps;
  ++counters_.episodes_accepted;
  replay_.Insert(std::move(episode));
  if (Blocked() && options_.learner.updates_per_step > 0) {
    const double paid = static_cast<double>(options_.learner.warmup_steps) +
                        static_cast<double>(counters_.updates) / options_.learner.updates_per_step;
    const double offset = static_cast<double>(counters_.transitions_inserted) - paid;
    limiter_offset_ = offset > 0 ? static_cast<uint64_t>(offset) : 0;
  }
  return "";
}

void Learner::SetGraph(const rl::SubgoalStructure& structure) {
  relabeler_.SetSubgoalStructure(structure);
  has_graph_ = true;
}

bool Learner::Blocked() const {
  return replay_.empty() || replay_.transitions() < options_.learner.warmup_steps ||
         (rl::UsesGraph(options_.method) && !has_graph_);
}

bool Learner::CanUpdate() const {
  return !Blocked() && limiter_.CanUpdate(LimiterInserted(), counters_.updates);
}

uint64_t Learner::UpdatesAllowed() const {
  return Blocked() ? 0 : limiter_.UpdatesAllowed(LimiterInserted(), counters_.updates);
}

UpdateStats Learner::Update() {
  relabeler_.Sample(replay_, options_.agent.sac.batch_size, &batch_);
  UpdateStats stats = agent_.Update(batch_);
  ++counters_.updates;
  return stats;
}

bool Learner::PublishDue() const {
  return !published_once_ ||
         counters_.updates >= published_at_update_ + options_.learner.publish_every_updates;
}

std::vector<float> Learner::TakePolicyWeights() {
  published_once_ = true;
  published_at_update_ = counters_.updates;
  ++counters_.policy_version;
  return agent_.PolicyWeights();
}

void Learner::SaveCheckpoint(const std::string& path) { agent_.SaveCheckpoint(path, counters_); }

void Learner::LoadCheckpoint(const std::string& path) {
  counters_ = agent_.LoadCheckpoint(path);
  // the replay is not saved: the limiter's warm-up restarts from the restored insert count
  published_at_update_ = counters_.updates;
}

}  // namespace srics::learner
