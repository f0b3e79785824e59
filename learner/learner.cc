#include "learner/learner.h"

#include <utility>

#include "common/nn/serialize.h"
#include "common/profile/phase_clock.h"
#include "common/rl/agent_shape.h"
#include "common/rl/seeds.h"

namespace srics::learner {

LearnerOptions LearnerOptionsFor(const config::Config& config, const rl::RunShape& shape) {
  LearnerOptions o;
  o.method = config.run.method;
  o.agent = config.agent;
  o.learner = config.learner;
  o.shape = shape.agent;
  o.limits = shape.limits;
  const auto& sampling = config.env.sampling;
  o.goal_region = {sampling.subgoal_low[0], sampling.subgoal_high[0], sampling.subgoal_low[1],
                   sampling.subgoal_high[1]};
  o.run_seed = config.run.seed;
  o.total_env_steps = config.run.total_env_steps;
  // HAC's subgoal records are checked against its horizon; other methods' episodes carry none
  o.limits.max_subgoal_steps = config.run.method == config::Method::kHac ? config.agent.hac.horizon : rl::kNoSubgoals;
  o.hac = {config.agent.hac.horizon, config.agent.hac.goal_threshold, config.agent.hac.hindsight_goals,
           shape.subgoal_box, config.agent.hac.bound_q};
  o.high_shape = shape.high;
  o.max_entities = shape.entities();
  return o;
}

Learner::Learner(const LearnerOptions& options)
    : options_(options),
      shape_(options.shape),
      replay_(options.learner.replay_capacity),
      relabeler_(options.method, options.agent.reward, options.learner.relabel, options.goal_region,
                 rl::DeriveSeed(options.run_seed, rl::SeedPurpose::kLearnerReplay), options.shape.goal_tokens),
      agent_(shape_, options.agent, rl::DeriveSeed(options.run_seed, rl::SeedPurpose::kLearnerAgent),
             options.learner.threads),
      limiter_(options.learner.updates_per_step, options.learner.warmup_steps, options.learner.rate_error_buffer) {
  if (options.method == config::Method::kHac) {
    BoundHacTargets(options.hac, &agent_);  // the low level's; HacLevels bounds the high one
    hac_ = std::make_unique<HacLevels>(
        options.hac, shape_, options.high_shape, options.agent, options.learner.replay_capacity, options.max_entities,
        rl::DeriveSeed(options.run_seed, rl::SeedPurpose::kLearnerAgent, 1), options.learner.threads);
  }
  const nn::GemmPrecision wanted = options.learner.precision == config::ProductPrecision::kBf16
                                       ? nn::GemmPrecision::kBf16
                                       : nn::GemmPrecision::kFp32;
  agent_.SetProductPrecision(wanted);
  if (hac_) hac_->high().SetProductPrecision(wanted);
}

std::string Learner::Ingest(rl::Episode episode) {
  std::string problem = rl::ValidateEpisode(episode, options_.limits);
  if (problem.empty() && episode.layout.entity_dim() != shape_.entity_dim)
    problem = "entity tokens of " + std::to_string(episode.layout.entity_dim()) + " floats, the networks take " +
              std::to_string(shape_.entity_dim);
  if (problem.empty() && relabeler_.full_goal() && episode.mode == rl::EpisodeMode::kTrain &&
      episode.goal.size() != static_cast<size_t>(2 * episode.layout.num_entities))
    problem = "SAC+HER training episodes need a full goal";
  if (problem.empty() && hac_ && episode.mode == rl::EpisodeMode::kTrain &&
      (episode.goal.size() != static_cast<size_t>(2 * episode.layout.num_entities) || episode.num_subgoals() == 0))
    problem = "HAC training episodes need a full goal and the high level's subgoals";
  if (problem.empty() && episode.mode == rl::EpisodeMode::kEval) problem = "evaluation episodes are not training data";
  if (!problem.empty()) {
    ++rejected_;
    return problem;
  }
  if (episode.mode == rl::EpisodeMode::kExplore && !options_.learner.exploration_into_replay) {
    ++exploration_skipped_;  // learner.exploration_into_replay: false
    return "";
  }
  if (BudgetReached()) {
    ++beyond_budget_;
    return "";
  }
  counters_.transitions_inserted += episode.num_steps;
  if (!rl::UsesGraph(options_.method) || has_graph_) counters_.training_env_steps += episode.num_steps;
  ++counters_.episodes_accepted;
  if (hac_) hac_->Add(episode);
  replay_.Insert(std::move(episode));
  if (Blocked() && options_.learner.updates_per_step > 0) {
    const double paid = static_cast<double>(options_.learner.warmup_steps) +
                        static_cast<double>(counters_.updates) / options_.learner.updates_per_step;
    const double offset = static_cast<double>(counters_.transitions_inserted) - paid;
    limiter_offset_ = offset > 0 ? static_cast<uint64_t>(offset) : 0;
  }
  return "";
}

void Learner::SetGraph(const rl::InteractionGraph& catalogue) {
  relabeler_.SetGraph(catalogue);
  has_graph_ = true;
}

void Learner::SetGraph(const rl::SubgoalStructure& structure) {
  relabeler_.SetSubgoalStructure(structure);
  has_graph_ = true;
}

bool Learner::Blocked() const {
  return replay_.empty() || replay_.transitions() < options_.learner.warmup_steps || (hac_ && !hac_->ready()) ||
         (rl::UsesGraph(options_.method) && !has_graph_);
}

bool Learner::CanUpdate() const { return !Blocked() && limiter_.CanUpdate(LimiterInserted(), counters_.updates); }

uint64_t Learner::UpdatesAllowed() const {
  return Blocked() ? 0 : limiter_.UpdatesAllowed(LimiterInserted(), counters_.updates);
}

double Learner::UpdateBacklog() const {
  return Blocked() ? 0.0 : limiter_.Target(LimiterInserted()) - static_cast<double>(counters_.updates);
}

UpdateStats Learner::Update() {
  UpdateStats stats;
  if (hac_) {
    profile::PhaseScope phase(profile::Phase::kSacUpdate);  // HAC samples inside its update
    stats = hac_->Update(agent_, options_.agent.sac.batch_size);
  } else {
    {
      profile::PhaseScope phase(profile::Phase::kReplaySampling);
      relabeler_.Sample(replay_, options_.agent.sac.batch_size, &batch_);
    }
    profile::PhaseScope phase(profile::Phase::kSacUpdate);
    stats = agent_.Update(batch_);
  }
  if (stats.non_finite) {
    ++non_finite_updates_;
    ++non_finite_in_a_row_;
  } else {
    non_finite_in_a_row_ = 0;
  }
  ++counters_.updates;
  return stats;
}

bool Learner::PublishDue() const {
  return !published_once_ || counters_.updates >= published_at_update_ + options_.learner.publish_every_updates;
}

std::vector<float> Learner::TakePolicyWeights() {
  published_once_ = true;
  published_at_update_ = counters_.updates;
  ++counters_.policy_version;
  return hac_ ? hac_->PolicyWeights(agent_) : agent_.PolicyWeights();
}

std::string Learner::PolicySignature() { return hac_ ? hac_->PolicySignature(agent_) : agent_.PolicySignature(); }

namespace {

// Version of the learner's own state section ("learner.state").
constexpr uint32_t kLearnerStateFormat = 1;

}  // namespace

void Learner::SaveCheckpoint(const std::string& path, int keep, files::FileSystem& fs) {
  std::vector<nn::CheckpointSection> sections = agent_.CheckpointSections(counters_);
  if (hac_) hac_->AppendCheckpointSections(counters_, &sections);
  nn::ByteWriter state;
  state.Put<uint32_t>(kLearnerStateFormat);
  state.Put<uint64_t>(limiter_offset_);
  state.Put<uint64_t>(rejected_);
  state.Put<uint64_t>(beyond_budget_);
  state.PutString(nn::RngState(relabeler_.rng()));
  sections.push_back({"learner.state", "", {}, state.Take()});
  sections.push_back({"replay", "", {}, replay_.Serialize()});
  nn::WriteCheckpoint(path, std::move(sections), keep, fs);
}

void Learner::LoadCheckpoint(const std::string& path) {
  const std::vector<nn::CheckpointSection> sections = nn::ReadCheckpoint(path);
  const nn::CheckpointSection* state_section = nullptr;
  const nn::CheckpointSection* replay_section = nullptr;
  for (const auto& s : sections) {
    if (s.name == "learner.state") state_section = &s;
    if (s.name == "replay") replay_section = &s;
  }
  // read the learner's own parts into locals first: a bad file changes nothing
  uint64_t limiter_offset = 0, rejected = 0, beyond_budget = 0;
  nn::Rng relabeler_rng = relabeler_.rng();
  ReplayBuffer replay(options_.learner.replay_capacity);
  if (state_section && replay_section) {
    const std::string what = "checkpoint " + path + ": section 'learner.state'";
    nn::ByteReader r(state_section->bytes, what);
    if (const auto format = r.Get<uint32_t>(); format != kLearnerStateFormat)
      throw nn::CheckpointError(what + ": format " + std::to_string(format) + " (this build reads " +
                                std::to_string(kLearnerStateFormat) + ")");
    limiter_offset = r.Get<uint64_t>();
    rejected = r.Get<uint64_t>();
    beyond_budget = r.Get<uint64_t>();
    nn::SetRngState(&relabeler_rng, r.GetString(), what);
    replay.Restore(replay_section->bytes, options_.limits, "checkpoint " + path + ": section 'replay'");
  } else if (state_section || replay_section) {
    throw nn::CheckpointError("checkpoint " + path + ": has " + (state_section ? "learner.state" : "replay") +
                              " but not " + (state_section ? "replay" : "learner.state"));
  }
  if (hac_) hac_->LoadCheckpointSections(sections, path);
  counters_ = agent_.LoadCheckpointSections(sections, path);
  published_at_update_ = counters_.updates;
  replay_restored_ = replay_section != nullptr;
  if (!replay_restored_) {
    // an old checkpoint without the replay: the warm-up refills it; the limiter counts from
    // the restored insert count (Ingest shifts its offset while blocked)
    replay_ = ReplayBuffer(options_.learner.replay_capacity);
    return;
  }
  replay_ = std::move(replay);
  if (hac_) hac_->Rebuild(replay_.contents());  // HAC's transitions follow from the episodes
  limiter_offset_ = limiter_offset;
  rejected_ = rejected;
  beyond_budget_ = beyond_budget;
  relabeler_.rng() = relabeler_rng;
}

}  // namespace srics::learner
