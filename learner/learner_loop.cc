#include "learner/learner_loop.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/nn/gemm.h"
#include "common/rl/ground_truth.h"

namespace srics::learner {

using Clock = std::chrono::steady_clock;

LearnerLoopOptions LearnerLoopOptionsFor(const config::Config& config, const rl::RunShape& shape,
                                         std::string checkpoint_path) {
  LearnerLoopOptions o;
  o.learner = LearnerOptionsFor(config, shape);
  o.num_entities = shape.entities();
  o.checkpoint_path = std::move(checkpoint_path);
  o.report_period_s = config.transport.status_period_s;
  if (!o.checkpoint_path.empty())
    o.training_log.path = (std::filesystem::path(o.checkpoint_path).parent_path() / "train.csv").string();
  o.training_log.every_env_steps = config.actors.eval_every_env_steps;
  o.training_log.epsilon = config.agent.reward.epsilon;
  o.training_log.success_threshold = config.env.success_threshold;
  o.training_log.table_graph = rl::GroundTruthGraph(config.env);
  o.rejected_log_interval_s = config.transport.rejected_log_interval_s;
  return o;
}

LearnerLoop::LearnerLoop(LearnerLoopOptions options, links::LearnerLink* link)
    : options_(std::move(options)),
      link_(link),
      learner_(options_.learner),
      refusals_log_(std::make_unique<logging::RateLimiter>(std::chrono::seconds(options_.rejected_log_interval_s))),
      training_log_(options_.training_log) {}

void LearnerLoop::Publish() {
  rl::WeightsUpdate w;
  w.parameters = learner_.TakePolicyWeights();
  // never publish what actors would refuse (and the writer would throw on): the weights of
  // the next publication, after more updates, go out instead
  if (const std::string problem = rl::ParameterProblem(w.parameters); !problem.empty()) {
    ++weights_withheld_;
    uint64_t suppressed = 0;
    if (refusals_log_->Allow(&suppressed))
      spdlog::error("weights v{} withheld: {} ({} withheld so far, {} warnings suppressed)",
                    learner_.counters().policy_version, problem, weights_withheld_, suppressed);
    return;
  }
  w.version = learner_.counters().policy_version;
  w.update_count = learner_.counters().updates;
  w.architecture = learner_.PolicySignature();
  ReserveVersions(w.version);
  link_->PublishWeights(std::move(w));
}

std::string LearnerLoop::VersionsPath() const { return options_.checkpoint_path + ".versions"; }

void LearnerLoop::ReserveVersions(uint64_t version) {
  if (options_.checkpoint_path.empty() || version <= versions_reserved_) return;
  // a block at a time: one small durable write per kVersionBlock publications
  const uint64_t reserved = version + kVersionBlock;
  try {
    files::WriteFileDurably(VersionsPath(), std::to_string(reserved) + "\n", *options_.file_system);
    versions_reserved_ = reserved;
  } catch (const std::exception& e) {
    // publishing goes on; a restart may then repeat versions above the checkpoint's
    uint64_t suppressed = 0;
    if (refusals_log_->Allow(&suppressed))
      spdlog::error("policy versions not reserved: {} ({} warnings suppressed)", e.what(), suppressed);
  }
}

void LearnerLoop::ContinueVersions() {
  std::ifstream in(VersionsPath());
  uint64_t reserved = 0;
  if (!(in >> reserved)) return;
  versions_reserved_ = reserved;
  const uint64_t current = learner_.counters().policy_version;
  if (current >= reserved) return;
  // every version up to `reserved` may have been published by a learner before this one
  learner_.SkipPolicyVersions(reserved - current);
  spdlog::info("policy versions continue above v{} (published before this start: {})", reserved, VersionsPath());
}

void LearnerLoop::Report(bool force) {
  const double since = std::chrono::duration<double>(Clock::now() - last_report_).count();
  if (!force && options_.report_period_s > 0 && since < options_.report_period_s) return;
  const LearnerCounters& c = learner_.counters();
  rl::LearnerReport r;
  r.updates = c.updates;
  r.transitions_inserted = c.transitions_inserted;
  r.update_backlog = learner_.UpdateBacklog();
  // With the budget's data in, the learner only works off the updates it owes: actors hold
  // back instead of playing episodes it would drop (in process they took most of the time the
  // last updates needed: 8-10 minutes at the end of a 150k-step run)
  if (learner_.BudgetReached() && !finished_)
    r.update_backlog = std::max(r.update_backlog, options_.learner.learner.rate_error_buffer + 1.0);
  r.budget_env_steps = options_.learner.total_env_steps;
  // the budget shows as done only once the learner has trained on it and published its final
  // weights: actors then run their last evaluation with those weights, not earlier ones
  r.training_env_steps = finished_ || r.budget_env_steps == 0
                             ? c.training_env_steps
                             : std::min<uint64_t>(c.training_env_steps, r.budget_env_steps - 1);
  r.replay_size = learner_.replay().transitions();
  r.episodes_accepted = c.episodes_accepted;
  r.episodes_rejected = learner_.episodes_rejected();
  r.policy_version = c.policy_version;
  r.q_loss = last_update_.q_loss;
  r.policy_loss = last_update_.policy_loss;
  r.alpha = last_update_.alpha;
  r.entropy = last_update_.entropy;
  r.mean_reward = last_update_.mean_reward;
  // rates over windows of at least a second (reports may come after every step)
  const double window = std::chrono::duration<double>(Clock::now() - rate_window_start_).count();
  if (window >= 1.0) {
    updates_per_second_ = (c.updates - updates_at_window_) / window;
    inserts_per_second_ = (c.transitions_inserted - inserted_at_window_) / window;
    rate_window_start_ = Clock::now();
    updates_at_window_ = c.updates;
    inserted_at_window_ = c.transitions_inserted;
  }
  r.updates_per_second = updates_per_second_;
  r.inserts_per_second = inserts_per_second_;
  link_->PublishStats(r);
  rl::NodeReport status;
  status.phase = learner_.CanUpdate() || c.updates > 0 ? rl::NodePhase::kTraining : rl::NodePhase::kWaiting;
  status.policy_version = c.policy_version;
  status.graph_version = graph_version_;
  status.steps = c.updates;
  status.dropped = r.episodes_rejected + duplicates_ + graphs_rejected_;
  for (auto [counter, count] :
       std::initializer_list<std::pair<const char*, uint64_t>>{{"episode.learner", r.episodes_rejected},
                                                               {"episode.duplicate", duplicates_},
                                                               {"graph.entities", graphs_rejected_},
                                                               {"update.nonfinite", learner_.non_finite_updates()},
                                                               {"weights.withheld", weights_withheld_}})
    if (count > 0) status.rejections[counter] = count;
  status.detail = "replay " + std::to_string(r.replay_size) + ", inserted " + std::to_string(c.transitions_inserted) +
                  (learner_.has_graph() || !rl::UsesGraph(options_.learner.method) ? "" : ", waiting for the graph");
  if (const HacLevels* hac = learner_.hac(); hac && c.updates > 0) {
    const UpdateStats& high = hac->last_high_update();
    status.detail +=
        fmt::format(", high level: Q loss {:.4g}, alpha {:.4g}, entropy {:.4g}", high.q_loss, high.alpha, high.entropy);
  }
  link_->PublishStatus(status);
  last_report_ = Clock::now();
}

void LearnerLoop::Start() {
  started_ = true;
  if (learner_.bf16_requested()) {
    if (learner_.product_precision() == nn::GemmPrecision::kBf16)
      spdlog::info("SAC update products in bf16 ({}), fp32 weights and sums", nn::GemmBackendDescription());
    else
      spdlog::warn(
          "learner.precision bf16, but products run in fp32 here ({}): bf16 needs oneDNN and a CPU with AVX-512 BF16 "
          "that DNNL_MAX_CPU_ISA allows",
          nn::GemmBackendDescription());
  }
  if (!options_.checkpoint_path.empty()) {
    LoadNewestCheckpoint();
    ContinueVersions();  // also without a checkpoint: a learner killed before its first one
  }
  checkpointed_at_ = learner_.counters().updates;
  // rows of train.csv beyond the checkpoint are trained again: dropped
  training_log_.ResumeAt(learner_.counters().training_env_steps);
  // actors start training once weights exist: publish the initial ones at once
  Publish();
  last_report_ = rate_window_start_ = Clock::now();
  updates_at_window_ = learner_.counters().updates;
  inserted_at_window_ = learner_.counters().transitions_inserted;
  Report(true);
}

void LearnerLoop::LoadNewestCheckpoint() {
  const std::string& path = options_.checkpoint_path;
  std::vector<std::string> set_aside;
  for (const std::string& generation : files::Generations(path)) {
    try {
      learner_.LoadCheckpoint(generation);
    } catch (const nn::CorruptCheckpointError& e) {
      // kept for inspection under another name, so that the next start does not trip on it
      const std::string aside = files::SetAside(generation, ".corrupt", *options_.file_system);
      spdlog::error("checkpoint {} is corrupt ({}): set aside as {}; trying the one before", generation, e.what(),
                    aside);
      set_aside.push_back(aside);
      continue;
    }
    // the restored replay's episodes count as ingested: one delivered again is refused
    for (const rl::Episode& e : learner_.replay().contents()) seen_.Remember(e.actor_id, e.episode_id);
    // weights published after that checkpoint carried higher versions than it records: skip
    // past every version that can have been used, so versions keep increasing for actors
    // (ContinueVersions then skips past every version ever published)
    const auto& l = options_.learner.learner;
    learner_.SkipPolicyVersions(l.checkpoint_every_updates / l.publish_every_updates + 2);
    spdlog::info("resumed from {}{}: {} updates, {} transitions inserted, policy v{}, replay {} transitions{}",
                 generation, generation == path ? "" : " (an older checkpoint: the newer ones were corrupt)",
                 learner_.counters().updates, learner_.counters().transitions_inserted,
                 learner_.counters().policy_version, learner_.replay().transitions(),
                 learner_.replay_restored() ? "" : " (an older checkpoint without the replay: refilling it)");
    return;
  }
  // none loaded: a run that had checkpoints must not start from scratch silently
  const std::string folder = std::filesystem::path(path).parent_path().string();
  const std::string name = std::filesystem::path(path).filename().string();
  std::error_code error;
  if (set_aside.empty())  // set aside by an earlier start: checkpoint.srics.corrupt, checkpoint.srics.1.corrupt, ...
    for (std::filesystem::directory_iterator it(folder.empty() ? "." : folder, error), end; !error && it != end;
         it.increment(error)) {
      const std::string file = it->path().filename().string();
      if (file.rfind(name + ".", 0) == 0 && file.find(".corrupt", name.size()) != std::string::npos)
        set_aside.push_back(it->path().string());
    }
  std::sort(set_aside.begin(), set_aside.end());
  if (set_aside.empty()) return;  // a new run
  std::string list;
  for (const std::string& file : set_aside) list += (list.empty() ? "" : ", ") + file;
  throw nn::CheckpointError("no usable checkpoint " + path + ": the run's checkpoints are corrupt (set aside: " + list +
                            "); remove them to start this run from scratch");
}

void LearnerLoop::SaveCheckpoint() {
  try {
    learner_.SaveCheckpoint(options_.checkpoint_path, options_.learner.learner.keep_checkpoints, *options_.file_system);
  } catch (const nn::CheckpointError& e) {
    // a full disk is no reason to stop training: the previous checkpoint stays; next period again
    ++checkpoint_failures_;
    spdlog::error("{} (at {} updates; {} failed checkpoint writes so far)", e.what(), learner_.counters().updates,
                  checkpoint_failures_);
  }
}

void LearnerLoop::FollowGraph() {
  auto g = link_->PollGraph();
  if (!g) return;
  if (const std::string problem = rl::GraphMismatch(g->graph, options_.num_entities); !problem.empty()) {
    ++graphs_rejected_;
    uint64_t suppressed = 0;
    if (refusals_log_->Allow(&suppressed))
      spdlog::warn("graph v{} ignored: {} ({} warnings suppressed)", g->version, problem, suppressed);
    return;
  }
  learner_.SetGraph(g->graph);  // over the catalogue: mapped per episode
  graph_version_ = g->version;
  spdlog::info("graph v{}: {}", g->version, rl::DescribeGraph(g->graph));
}

StepResult LearnerLoop::Step(std::chrono::milliseconds wait) {
  if (finished_) return StepResult::kDone;
  if (!started_) Start();
  episodes_.clear();
  const bool work = learner_.CanUpdate();
  link_->TakeEpisodes(&episodes_, 64, work ? std::chrono::milliseconds(0) : wait);
  for (auto& e : episodes_) {
    // measured before Ingest takes the episode, counted only when it was stored
    const auto figures = training_log_.Measure(e, learner_.SubgoalPartnerOf(e));
    const uint64_t stored_before = learner_.counters().episodes_accepted;
    const uint32_t actor_id = e.actor_id;
    const uint64_t episode_id = e.episode_id;
    uint64_t suppressed = 0;
    if (seen_.Seen(actor_id, episode_id)) {  // delivered again: never trained on twice
      ++duplicates_;
      if (refusals_log_->Allow(&suppressed))
        spdlog::warn("episode {} of actor {} refused: ingested before ({} duplicates so far, {} warnings suppressed)",
                     episode_id, actor_id, duplicates_, suppressed);
      continue;
    }
    const std::string problem = learner_.Ingest(std::move(e));
    if (problem.empty()) seen_.Remember(actor_id, episode_id);  // a refused one burns no id
    if (!problem.empty() && refusals_log_->Allow(&suppressed))
      spdlog::warn("episode rejected: {} ({} rejected so far, {} warnings suppressed)", problem,
                   learner_.episodes_rejected(), suppressed);
    if (figures && learner_.counters().episodes_accepted > stored_before) training_log_.Add(*figures);
  }
  FollowGraph();
  int updates = 0;
  auto may_update = [&] {
    return learner_.CanUpdate() &&
           (!options_.updates_on_ratio_only || learner_.BudgetReached() || learner_.UpdateBacklog() >= 1.0);
  };
  for (; updates < options_.max_updates_per_step && may_update(); ++updates) {
    const UpdateStats stats = learner_.Update();
    if (!stats.non_finite) {
      last_update_ = stats;
      continue;
    }
    uint64_t suppressed = 0;
    if (refusals_log_->Allow(&suppressed))
      spdlog::warn("update {} skipped: a non-finite value in the {} ({} so far, {} warnings suppressed)",
                   learner_.counters().updates, stats.non_finite_stage, learner_.non_finite_updates(), suppressed);
    const int limit = options_.learner.learner.max_skipped_updates_in_a_row;
    if (limit > 0 && learner_.non_finite_in_a_row() >= static_cast<uint64_t>(limit))
      throw LearningDivergedError("learning diverged: the last " + std::to_string(learner_.non_finite_in_a_row()) +
                                  " updates (to update " + std::to_string(learner_.counters().updates) +
                                  ") all met a non-finite value, the last in the " + stats.non_finite_stage +
                                  ", so no network changes any more; the run stops rather than train on unchanged "
                                  "(learner.max_skipped_updates_in_a_row: " +
                                  std::to_string(limit) + ")");
  }
  if (learner_.counters().updates > 0 && learner_.PublishDue()) Publish();
  if (!options_.checkpoint_path.empty() &&
      learner_.counters().updates >= checkpointed_at_ + options_.learner.learner.checkpoint_every_updates) {
    SaveCheckpoint();
    checkpointed_at_ = learner_.counters().updates;
  }
  training_log_.Advance(learner_.counters().training_env_steps);
  Report(false);
  if (learner_.BudgetReached() && !learner_.CanUpdate()) {
    Finish();
    spdlog::info("learner done: {} updates, {} transitions, policy v{}", learner_.counters().updates,
                 learner_.counters().transitions_inserted, learner_.counters().policy_version);
    return StepResult::kDone;
  }
  return updates > 0 || !episodes_.empty() ? StepResult::kWorked : StepResult::kIdle;
}

void LearnerLoop::Finish() {
  if (finished_) return;
  finished_ = true;
  training_log_.Advance(learner_.counters().training_env_steps, /*force=*/true);
  // final weights first, then the stats that tell actors the budget is done
  Publish();
  if (!options_.checkpoint_path.empty()) SaveCheckpoint();
  if (options_.final_weights_grace.count() > 0) std::this_thread::sleep_for(options_.final_weights_grace);
  Report(true);
}

int LearnerLoop::Run(const std::atomic<bool>& stop) {
  while (!stop)
    if (Step(std::chrono::milliseconds(50)) == StepResult::kDone) return 0;
  Finish();
  spdlog::info("learner stopped: {} updates, {} transitions, policy v{}", learner_.counters().updates,
               learner_.counters().transitions_inserted, learner_.counters().policy_version);
  return 0;
}

}  // namespace srics::learner
