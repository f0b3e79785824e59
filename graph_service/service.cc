#include "graph_service/service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "common/rl/agent_shape.h"
#include "common/rl/graph.h"
#include "common/rl/seeds.h"
#include "graph_service/readout.h"

namespace srics::graph_service {

const char* PhaseName(Progress::Phase phase) {
  switch (phase) {
    case Progress::Phase::kLoading: return "loading";
    case Progress::Phase::kCollecting: return "collecting";
    case Progress::Phase::kTraining: return "training";
    case Progress::Phase::kPublished: return "published";
    case Progress::Phase::kStopped: return "stopped";
  }
  return "?";
}

GraphService::GraphService(const config::GraphConfig& config, const ServiceOptions& options, EpisodeSource* source,
                           GraphSink* sink, ProgressCallback on_progress)
    : config_(config), options_(options), source_(source), sink_(sink), on_progress_(std::move(on_progress)) {
  if (source_ == nullptr || sink_ == nullptr) throw std::invalid_argument("GraphService: source and sink are required");
  progress_.target_episodes = config_.episodes;
  if (options_.shape) {
    // the run's shape, before any episode: no peer decides it by being first
    const DatasetShape& shape = *options_.shape;
    if (shape.layout.num_entities < 2)
      throw std::invalid_argument("GraphService: the environment needs at least 2 entities");
    state_.data = std::make_unique<GraphDataset>(GraphDataset::ForShape(shape, config_.episode_steps));
    // the cut read-out swaps senders between episodes by position, which mixes identities
    // when episodes present different objects
    if (state_.data->combinations() && config_.readout == config::GraphReadout::kCut)
      throw std::invalid_argument(
          "graph.readout: cut is not built for environments with object_sets (use mean_weight)");
  }
}

std::string GraphService::graph_path() const {
  return options_.state_dir.empty() ? "" : options_.state_dir + "/graph.json";
}

std::string GraphService::training_path() const {
  return options_.state_dir.empty() ? "" : options_.state_dir + "/graph_training.srics";
}

void GraphService::SyncProgress() {
  progress_.dropped = state_.dropped;
  progress_.refine_episodes = state_.refine_episodes;
  if (state_.trainer && progress_.onsets_at_a_distance.empty()) {
    progress_.onsets_at_a_distance = state_.trainer->onsets_at_a_distance();
    progress_.onsets_while_moving = state_.trainer->onsets_while_moving();
    progress_.tied_by_evidence = state_.trainer->tied_by_evidence();
    progress_.tie_evidence_counted = state_.trainer->tie_evidence_counted();
  }
}

void GraphService::Report() {
  SyncProgress();
  progress_.elapsed_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (on_progress_) on_progress_(progress_);
}

ServiceOptions ServiceOptionsFor(const config::Config& config, const rl::RunShape& run_shape,
                                 const std::string& state_dir) {
  ServiceOptions options;
  options.state_dir = state_dir;
  options.seed = rl::DeriveSeed(config.run.seed, rl::SeedPurpose::kGraphService);
  options.limits = run_shape.limits;
  const rl::EnvironmentShape& shape = run_shape.full;
  options.shape = DatasetShape{shape.layout, shape.entity_kinds, shape.action_dim, shape.episode_kinds};
  // footprints: the hand's box, then every object of the catalogue (graph entities)
  options.contact_radius = {std::hypot(config.env.hand.half_size[0], config.env.hand.half_size[1])};
  for (const config::ObjectConfig& object : config::EffectiveObjects(config.env))
    options.contact_radius.push_back(config::BoundingRadius(object));
  options.status_period_s = config.transport.status_period_s;
  options.refine_episode_steps = config.actors.train_episode_steps;
  return options;
}

namespace {

// Renames an unusable file to <path>.rejected (kept for inspection) and warns:
// "graph service: <what> (<error>); moved to <path>.rejected, <then>".
void SetAside(const std::string& path, const char* what, const std::exception& error, const char* then) {
  const std::string aside = path + ".rejected";
  std::error_code ec;
  std::filesystem::rename(path, aside, ec);
  spdlog::warn("graph service: {} ({}); moved to {}, {}", what, error.what(), aside, then);
}

rl::NodePhase NodePhaseOf(Progress::Phase phase) {
  switch (phase) {
    case Progress::Phase::kLoading: return rl::NodePhase::kStarting;
    case Progress::Phase::kCollecting: return rl::NodePhase::kWaiting;
    case Progress::Phase::kTraining: return rl::NodePhase::kTraining;
    case Progress::Phase::kPublished: return rl::NodePhase::kWaiting;
    case Progress::Phase::kStopped: return rl::NodePhase::kStopping;
  }
  return rl::NodePhase::kFailed;
}

}  // namespace

void GraphService::PublishStatus(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_status_).count() < options_.status_period_s) return;
  last_status_ = now;
  SyncProgress();
  const Progress& p = progress_;
  rl::NodeReport r;
  r.phase = NodePhaseOf(p.phase);
  r.graph_version = p.published_version;
  r.steps = static_cast<uint64_t>(p.updates);
  r.dropped = static_cast<uint64_t>(p.dropped);
  // explore episodes refused by the service's own checks (the run's shape, steps, limits)
  if (p.dropped > 0) r.rejections["episode.graph"] = static_cast<uint64_t>(p.dropped);
  if (p.skipped_updates > 0) r.rejections["update.nonfinite"] = static_cast<uint64_t>(p.skipped_updates);
  if (p.phase != status_phase_ || status_phase_start_ == std::chrono::steady_clock::time_point{}) {
    status_phase_ = p.phase;
    status_phase_start_ = now;
  }
  // the phase's ETA at its rate so far: collecting to the data set's size; training to
  // max_updates, an upper bound (a stable graph ends it sooner)
  const double in_phase = std::chrono::duration<double>(now - status_phase_start_).count();
  auto eta = [&](double done, double total, const char* prefix) {
    if (done <= 0 || total <= done || in_phase <= 0) return std::string();
    const long seconds = std::lround(in_phase * (total - done) / done);
    return std::string(", ETA ") + prefix + std::to_string(seconds / 60) + "m" + (seconds % 60 < 10 ? "0" : "") +
           std::to_string(seconds % 60) + "s";
  };
  const bool training = p.phase == Progress::Phase::kTraining;
  r.detail = std::string(PhaseName(p.phase)) + ": " + std::to_string(p.episodes) + "/" +
             std::to_string(p.target_episodes) + " episodes, " + std::to_string(p.updates) +
             (training ? " of at most " + std::to_string(config_.max_updates) : std::string()) + " updates" +
             (p.phase == Progress::Phase::kCollecting ? eta(p.episodes, p.target_episodes, "")
              : training                              ? eta(static_cast<double>(p.updates), config_.max_updates, "<= ")
                                                      : std::string()) +
             (p.held_out_loss >= 0 ? ", held-out " + std::to_string(p.held_out_loss) : "") +
             (p.refining ? ", refining from " + std::to_string(p.refine_episodes) + " training episodes" : "") +
             (p.graph.empty() ? "" : ", " + p.graph);
  sink_->PublishStatus(r);
}

StepResult GraphService::Step(std::chrono::milliseconds wait) {
  if (!started_) {
    started_ = true;
    start_ = std::chrono::steady_clock::now();
    progress_.phase = Progress::Phase::kLoading;
    Report();
    PublishStatus(true);
    if (LoadSaved()) {
      if (config_.refine_after_publish) {
        // the refinement goes on from its training state, towards the next version
        next_version_ = published_->version + 1;
        if (LoadTraining() && state_.trainer) {
          progress_.phase = Progress::Phase::kPublished;
          StartRefinement();
        } else {
          spdlog::warn("graph service: no training state in {} to refine from; graph v{} stays", options_.state_dir,
                       published_->version);
        }
        Report();
      }
      return StepResult::kWorked;
    }
    progress_.phase = Progress::Phase::kCollecting;
    if (LoadTraining()) return StepResult::kWorked;
    Report();
  }
  StepResult result = StepResult::kWorked;
  switch (progress_.phase) {
    case Progress::Phase::kLoading:
    case Progress::Phase::kCollecting: result = CollectStep(wait); break;
    case Progress::Phase::kTraining: TrainStep(); break;
    case Progress::Phase::kPublished: {
      if (refining_) {
        result = RefineStep(wait);
        break;
      }
      // keep the episode topic flowing: what arrives now is not needed
      std::vector<rl::Episode> unused;
      source_closed_ |= !source_->Poll(wait, &unused);
      result = StepResult::kIdle;
      break;
    }
    case Progress::Phase::kStopped: result = StepResult::kDone; break;
  }
  SyncProgress();
  PublishStatus(false);
  return result;
}

int GraphService::Run(const std::atomic<bool>& stop) {
  while (!stop.load()) {
    const StepResult result = Step(options_.poll_timeout);
    if (progress_.phase == Progress::Phase::kPublished) return 0;
    if (result == StepResult::kDone) return 1;
  }
  Stop();
  return 1;
}

void GraphService::Stop() {
  progress_.phase = Progress::Phase::kStopped;
  Report();
  PublishStatus(true);
}

bool GraphService::LoadSaved() {
  const std::string path = graph_path();
  if (path.empty() || !std::filesystem::exists(path)) return false;
  try {
    LearnedGraph saved = LoadGraph(path);
    spdlog::info("graph service: re-publishing saved graph version {} ({}) from {}", saved.version,
                 rl::DescribeGraph(saved.graph), path);
    sink_->Publish(ToGraphUpdate(saved));
    progress_.phase = Progress::Phase::kPublished;
    progress_.published_version = saved.version;
    ShowGraph(saved);
    progress_.held_out_loss = saved.held_out_loss;
    progress_.updates = saved.updates;
    progress_.episodes = saved.episodes;
    published_ = std::move(saved);
    Report();
    return true;
  } catch (const std::exception& e) {
    // an unusable file is kept aside for inspection and the graph is learned again
    SetAside(path, "saved graph rejected", e, "learning again");
    return false;
  }
}

void GraphService::SaveTraining() {
  const std::string path = training_path();
  if (path.empty() || !state_.data) return;
  try {
    std::filesystem::create_directories(options_.state_dir);
    nn::WriteCheckpoint(path, state_.Save());
    saved_episodes_ = state_.data->size();
  } catch (const std::exception& e) {
    // the run goes on; a restart would only redo more work
    spdlog::warn("graph service: saving the training state failed: {}", e.what());
  }
}

bool GraphService::LoadTraining() {
  const std::string path = training_path();
  if (path.empty() || !state_.data || !std::filesystem::exists(path)) return false;
  try {
    TrainingState restored =
        TrainingState::Restore(nn::ReadCheckpoint(path), path, *state_.data, config_,
                               {options_.seed, options_.refine_episode_steps, options_.contact_radius});
    // everything fits: take it over
    const int stable = restored.stable;
    state_ = std::move(restored);
    saved_episodes_ = state_.data->size();
    progress_.episodes = state_.data->size();
    if (state_.trainer) {
      progress_.phase = Progress::Phase::kTraining;
      action_entity_ = SelectActionEntity(*state_.data);
      action_correlation_ = ActionCorrelations(*state_.data);
      if (state_.trainer->updates() > 0) {
        EvaluateGraph();  // the graph the saved state had, to compare the next one with
        state_.stable = stable;
        progress_.stable_evaluations = state_.stable;
      }
    }
    spdlog::info("graph service: resumed from {}: {} of {} episodes, {} GNN updates", path, state_.data->size(),
                 config_.episodes, state_.trainer ? state_.trainer->updates() : 0);
    Report();
    return true;
  } catch (const std::exception& e) {
    SetAside(path, "training state not resumed", e, "starting over");
    return false;
  }
}

StepResult GraphService::CollectStep(std::chrono::milliseconds wait) {
  std::vector<rl::Episode> batch;
  const bool open = source_->Poll(wait, &batch);
  for (const rl::Episode& episode : batch) {
    if (progress_.episodes >= config_.episodes) break;
    if (episode.mode != rl::EpisodeMode::kExplore) continue;  // other modes are not ours
    std::string problem = rl::ValidateEpisode(episode, options_.limits);
    if (problem.empty() && episode.num_steps != config_.episode_steps)
      problem = "episode has " + std::to_string(episode.num_steps) + " steps, expected " +
                std::to_string(config_.episode_steps);
    if (problem.empty() && !state_.data) {
      // no shape given (toy worlds in tests): the first valid episode fixes it
      try {
        state_.data = std::make_unique<GraphDataset>(GraphDataset::ShapedLike(episode));
        if (state_.data->num_entities() < 2) {
          state_.data.reset();
          problem = "fewer than 2 entities";
        }
      } catch (const std::exception& e) {
        problem = e.what();
      }
    }
    if (problem.empty() && state_.data) problem = state_.data->Add(episode);
    if (problem.empty()) {
      ++progress_.episodes;
    } else {
      ++state_.dropped;
      progress_.last_drop_reason = problem;
    }
  }
  if (progress_.episodes >= config_.episodes) {
    StartTraining();
    SaveTraining();
    return StepResult::kWorked;
  }
  // a tenth of the data set at a time: a restart collects at most that again
  if (progress_.episodes - saved_episodes_ >= std::max(1, config_.episodes / 10)) SaveTraining();
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ > std::chrono::seconds(1)) {
    Report();
    last_report_ = now;
  }
  if (!open) {
    spdlog::warn("graph service: episode source closed after {} of {} episodes", progress_.episodes, config_.episodes);
    progress_.phase = Progress::Phase::kStopped;
    Report();
    return StepResult::kDone;
  }
  return batch.empty() ? StepResult::kIdle : StepResult::kWorked;
}

void GraphService::StartTraining() {
  progress_.phase = Progress::Phase::kTraining;
  state_.data->Split(config_.held_out_fraction, options_.seed);
  state_.trainer = std::make_unique<GnnTrainer>(config_, *state_.data, options_.seed);
  state_.trainer->SetContactRadii(options_.contact_radius);
  action_entity_ = SelectActionEntity(*state_.data);
  action_correlation_ = ActionCorrelations(*state_.data);
  state_.stable = 0;
  Report();
}

void GraphService::UpdateModel() {
  state_.trainer->Update();
  if (state_.trainer->skipped_in_a_row() == 0) return;
  progress_.skipped_updates = state_.trainer->skipped_updates();
  if (state_.trainer->skipped_in_a_row() == 1)  // once per streak: GnnTrainingDivergedError ends a long one
    spdlog::warn(
        "graph service: GNN update {} skipped: a non-finite loss or an unusable gradient "
        "({} so far; graph.max_skipped_updates_in_a_row: {})",
        state_.trainer->updates(), state_.trainer->skipped_updates(), config_.max_skipped_updates_in_a_row);
}

void GraphService::TrainStep() {
  for (int i = 0; i < options_.updates_per_step && state_.trainer->updates() < config_.max_updates; ++i) {
    UpdateModel();
    if (state_.trainer->updates() % config_.eval_every_updates == 0) break;  // evaluate at the boundary
  }
  const bool at_eval =
      state_.trainer->updates() % config_.eval_every_updates == 0 || state_.trainer->updates() >= config_.max_updates;
  if (!at_eval) return;
  EvaluateGraph();
  const bool stable = state_.stable >= config_.stable_evaluations && state_.trainer->updates() >= config_.min_updates;
  if (stable || state_.trainer->updates() >= config_.max_updates)
    Finish();
  else
    SaveTraining();
}

void GraphService::EvaluateGraph() {
  // held-out loss and the thresholded graph of the read-out's edge scores
  const EdgeStatistics stats = state_.trainer->Evaluate();
  const bool cut = config_.readout == config::GraphReadout::kCut;
  const std::vector<double> scores = ReadOutScores(stats, config_, action_entity_);
  LearnedGraph graph = AggregateGraph(state_.data->graph_entities(), scores,
                                      cut ? config_.cut_threshold : config_.threshold, action_entity_);
  graph.readout = cut ? "cut" : state_.trainer->ApartWeights() ? "mean_weight_apart" : "mean_weight";
  graph.mean_weights = stats.mean_weight;
  graph.held_out_loss = stats.held_out_mse;
  graph.updates = state_.trainer->updates();
  graph.episodes = state_.data->size();
  graph.action_correlation = action_correlation_;
  const std::vector<uint16_t> kinds = state_.data->graph_kinds();
  graph.entity_kinds.assign(kinds.begin(), kinds.end());
  // graphs of the warm-up and the KL ramp (edges open or not yet pruned) never count as
  // stable: only evaluations after the full KL weight is reached are compared
  const bool gated = state_.trainer->Settled();
  state_.stable = gated && current_ && SameStructure(current_->graph, graph.graph) ? state_.stable + 1 : 0;
  if (gated && (!state_.lowest_loss || graph.held_out_loss < state_.lowest_loss->held_out_loss))
    state_.lowest_loss = graph;
  current_ = std::move(graph);
  progress_.updates = state_.trainer->updates();
  progress_.train_loss = state_.trainer->last_mse();
  progress_.held_out_loss = stats.held_out_mse;
  progress_.held_out_zero_loss = stats.held_out_zero_mse;
  progress_.entity_loss = stats.held_out_entity_mse;
  progress_.entity_zero_loss = stats.held_out_entity_zero_mse;
  progress_.stable_evaluations = state_.stable;
  ShowGraph(*current_);
  Report();
}

void GraphService::ShowGraph(const LearnedGraph& graph) {
  progress_.graph = rl::DescribeGraph(graph.graph);
  progress_.edge_scores = graph.edge_scores;
  progress_.mean_weights = graph.mean_weights;
}

void GraphService::Finish() {
  if (config_.publish == config::GraphPublish::kLowestHeldOutLoss && state_.lowest_loss &&
      state_.lowest_loss->updates != current_->updates) {
    spdlog::info(
        "graph service: publishing the graph of update {} (held-out loss {:.3g}, the lowest), not of {} ({:.3g})",
        state_.lowest_loss->updates, state_.lowest_loss->held_out_loss, current_->updates, current_->held_out_loss);
    current_ = state_.lowest_loss;
    ShowGraph(*current_);
  }
  PublishCurrent();
  if (config_.refine_after_publish) {
    StartRefinement();
    SaveTraining();
  } else if (!training_path().empty() && std::filesystem::exists(graph_path())) {
    // graph.json is the product now; the training state is not needed again
    std::error_code ec;
    std::filesystem::remove(training_path(), ec);
  }
}

void GraphService::PublishCurrent() {
  LearnedGraph graph = *current_;
  graph.version = next_version_++;
  if (!options_.state_dir.empty()) {
    std::filesystem::create_directories(options_.state_dir);
    try {
      if (options_.render_pictures) {
        const std::string missing = SaveGraphWithPictures(graph, options_.state_dir + "/graph");
        if (!missing.empty()) spdlog::warn("graph service: could not render {}", missing);
      } else {
        SaveGraph(graph, graph_path());
      }
    } catch (const std::exception& e) {
      spdlog::error("graph service: saving the graph failed: {}", e.what());
    }
  }
  sink_->Publish(ToGraphUpdate(graph));
  progress_.phase = Progress::Phase::kPublished;
  progress_.published_version = graph.version;
  published_ = std::move(graph);
  Report();
  PublishStatus(true);
}

int GraphService::RefineCapacity() const {
  return std::max<int>(1, static_cast<int>(state_.data->train_episodes().size()));
}

double GraphService::RefineShare() const {
  return state_.refine_data
             ? config_.refine_share * std::min(1.0, static_cast<double>(state_.refine_data->size()) / RefineCapacity())
             : 0.0;
}

void GraphService::StartRefinement() {
  if (options_.refine_episode_steps < config_.window) {
    spdlog::warn("graph service: no refinement: training episodes of {} steps are shorter than a window ({})",
                 options_.refine_episode_steps, config_.window);
    return;
  }
  if (!state_.refine_data)
    state_.refine_data =
        std::make_unique<GraphDataset>(state_.data->ForTrainingEpisodes(options_.refine_episode_steps));
  state_.trainer->SetRefinementData(state_.refine_data.get(), RefineShare());
  refining_ = true;
  progress_.refining = true;
  spdlog::info("graph service: refining graph v{} from the run's training episodes ({} so far)", published_->version,
               state_.refine_episodes);
}

StepResult GraphService::RefineStep(std::chrono::milliseconds wait) {
  std::vector<rl::Episode> batch;
  source_closed_ |= !source_->Poll(refine_budget_ > 0 ? std::chrono::milliseconds(0) : wait, &batch);
  const int capacity = RefineCapacity();
  int taken = 0;
  for (const rl::Episode& episode : batch) {
    // training episodes only: late explore episodes are the first graph's kind of data
    if (episode.mode != rl::EpisodeMode::kTrain) continue;
    std::string problem = rl::ValidateEpisode(episode, options_.limits);
    const bool full = state_.refine_data->size() >= capacity;
    if (problem.empty())
      problem = full ? state_.refine_data->Replace(state_.refine_cursor, episode) : state_.refine_data->Add(episode);
    if (!problem.empty()) {
      ++state_.dropped;
      progress_.last_drop_reason = problem;
      continue;
    }
    if (full) state_.refine_cursor = (state_.refine_cursor + 1) % capacity;  // the oldest goes next
    ++state_.refine_episodes;
    ++taken;
    refine_budget_ += config_.refine_updates_per_episode;
    if (state_.refine_episodes % capacity == 0) {
      // the ring holds a new set of training episodes: every gate is decided again on the
      // mixed data (a closed gate would hardly reopen), and only graphs after the new
      // warm-up and ramp count towards a publication
      state_.trainer->RestartSchedule();
      state_.refine_decided = true;
      state_.stable = 0;
      spdlog::info("graph service: {} training episodes in: the edges are decided again (warm-up and KL ramp)",
                   state_.refine_episodes);
    }
  }
  if (taken > 0) state_.trainer->SetRefinementData(state_.refine_data.get(), RefineShare());
  int done = 0;
  while (done < options_.updates_per_step && refine_budget_ > 0) {
    UpdateModel();
    --refine_budget_;
    ++done;
    if (state_.trainer->updates() % config_.eval_every_updates != 0) continue;
    EvaluateGraph();
    // only graphs of a decision on training episodes, not the drift of the first graph's model
    if (state_.refine_decided && !SameStructure(current_->graph, published_->graph) &&
        state_.stable >= config_.stable_evaluations) {
      spdlog::info("graph service: the refined graph ({}) differs from v{} ({}) for {} evaluations: publishing v{}",
                   rl::DescribeGraph(current_->graph), published_->version, rl::DescribeGraph(published_->graph),
                   state_.stable, next_version_);
      PublishCurrent();
    }
    SaveTraining();
    break;
  }
  progress_.updates = state_.trainer->updates();
  if (taken > 0 || done > 0) Report();
  return taken > 0 || done > 0 ? StepResult::kWorked : StepResult::kIdle;
}

}  // namespace srics::graph_service
