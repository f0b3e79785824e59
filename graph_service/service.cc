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
    data_ = std::make_unique<GraphDataset>(GraphDataset::ForShape(shape, config_.episode_steps));
    // the cut read-out swaps senders between episodes by position, which mixes identities
    // when episodes present different objects
    if (data_->combinations() && config_.readout == config::GraphReadout::kCut)
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

void GraphService::Report() {
  progress_.elapsed_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (on_progress_) on_progress_(progress_);
}

ServiceOptions ServiceOptionsFor(const config::Config& config, const std::string& state_dir) {
  ServiceOptions options;
  options.state_dir = state_dir;
  options.seed = rl::DeriveSeed(config.run.seed, rl::SeedPurpose::kGraphService);
  options.limits = rl::EpisodeLimitsFor(config.env);
  const rl::EnvironmentShape shape = rl::FullEnvironmentShapeFor(config.env);
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

// Renames an unusable file to <path>.rejected (kept for inspection); returns the new name.
std::string SetAside(const std::string& path) {
  const std::string aside = path + ".rejected";
  std::error_code ec;
  std::filesystem::rename(path, aside, ec);
  return aside;
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
        if (LoadTraining() && trainer_) {
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
    progress_.graph = rl::DescribeGraph(saved.graph);
    progress_.edge_scores = saved.edge_scores;
    progress_.mean_weights = saved.mean_weights;
    progress_.held_out_loss = saved.held_out_loss;
    progress_.updates = saved.updates;
    progress_.episodes = saved.episodes;
    published_ = std::move(saved);
    Report();
    return true;
  } catch (const std::exception& e) {
    // an unusable file is kept aside for inspection and the graph is learned again
    const std::string aside = SetAside(path);
    spdlog::warn("graph service: saved graph rejected ({}); moved to {}, learning again", e.what(), aside);
    return false;
  }
}

void GraphService::SaveTraining() {
  const std::string path = training_path();
  if (path.empty() || !data_) return;
  nn::ByteWriter data, counters;
  data_->Save(data);
  counters.Put<int32_t>(progress_.dropped);
  counters.Put<int32_t>(stable_);
  // the refinement's (absent from states written before it existed)
  counters.Put<int32_t>(refine_cursor_);
  counters.Put<int32_t>(progress_.refine_episodes);
  counters.Put<uint8_t>(refine_decided_ ? 1 : 0);
  std::vector<nn::CheckpointSection> sections = {{"graph.data", "", {}, data.Take()},
                                                 {"graph.service", "", {}, counters.Take()}};
  if (refine_data_) {
    nn::ByteWriter refine;
    refine_data_->Save(refine);
    sections.push_back({"graph.refine_data", "", {}, refine.Take()});
  }
  if (trainer_)
    for (nn::CheckpointSection& section : trainer_->SaveState()) sections.push_back(std::move(section));
  try {
    std::filesystem::create_directories(options_.state_dir);
    nn::WriteCheckpoint(path, std::move(sections));
    saved_episodes_ = data_->size();
  } catch (const std::exception& e) {
    // the run goes on; a restart would only redo more work
    spdlog::warn("graph service: saving the training state failed: {}", e.what());
  }
}

bool GraphService::LoadTraining() {
  const std::string path = training_path();
  if (path.empty() || !data_ || !std::filesystem::exists(path)) return false;
  try {
    const std::vector<nn::CheckpointSection> sections = nn::ReadCheckpoint(path);
    auto data = std::make_unique<GraphDataset>(data_->EmptyCopy());
    nn::ByteReader data_bytes(nn::FindSection(sections, "graph.data", path).bytes, path + ": graph.data");
    data->Load(data_bytes);
    if (data->size() > config_.episodes)
      throw nn::CheckpointError(path + ": " + std::to_string(data->size()) + " episodes, the run's graph.episodes is " +
                                std::to_string(config_.episodes));
    nn::ByteReader counters(nn::FindSection(sections, "graph.service", path).bytes, path + ": graph.service");
    const int dropped = counters.Get<int32_t>();
    const int stable = counters.Get<int32_t>();
    int refine_cursor = 0, refine_episodes = 0;
    bool refine_decided = false;
    if (!counters.done()) {
      refine_cursor = counters.Get<int32_t>();
      refine_episodes = counters.Get<int32_t>();
      refine_decided = counters.Get<uint8_t>() != 0;
    }
    std::unique_ptr<GraphDataset> refine;
    if (const auto section = std::find_if(sections.begin(), sections.end(),
                                          [](const nn::CheckpointSection& s) { return s.name == "graph.refine_data"; });
        section != sections.end() && config_.refine_after_publish) {
      refine = std::make_unique<GraphDataset>(data->ForTrainingEpisodes(options_.refine_episode_steps));
      nn::ByteReader refine_bytes(section->bytes, path + ": graph.refine_data");
      refine->Load(refine_bytes);
      if (refine_cursor < 0 || refine_cursor >= std::max(1, refine->size()) || refine_episodes < refine->size())
        throw nn::CheckpointError(path + ": the refinement's counters do not fit its " +
                                  std::to_string(refine->size()) + " episodes");
    }
    const bool has_trainer =
        std::any_of(sections.begin(), sections.end(), [](const nn::CheckpointSection& s) { return s.name == "gnn"; });
    std::unique_ptr<GnnTrainer> trainer;
    if (data->size() >= config_.episodes) {
      data->Split(config_.held_out_fraction, options_.seed);
      trainer = std::make_unique<GnnTrainer>(config_, *data, options_.seed);
      trainer->SetContactRadii(options_.contact_radius);
      if (has_trainer) trainer->LoadState(sections, path);
    }
    // everything fits: take it over
    data_ = std::move(data);
    refine_data_ = std::move(refine);
    refine_cursor_ = refine_cursor;
    refine_decided_ = refine_decided;
    progress_.refine_episodes = refine_episodes;
    saved_episodes_ = data_->size();
    progress_.episodes = data_->size();
    progress_.dropped = dropped;
    if (trainer) {
      progress_.phase = Progress::Phase::kTraining;
      trainer_ = std::move(trainer);
      action_entity_ = SelectActionEntity(*data_);
      action_correlation_ = ActionCorrelations(*data_);
      if (trainer_->updates() > 0) {
        EvaluateGraph();  // the graph the saved state had, to compare the next one with
        stable_ = stable;
        progress_.stable_evaluations = stable_;
      }
    }
    spdlog::info("graph service: resumed from {}: {} of {} episodes, {} GNN updates", path, data_->size(),
                 config_.episodes, trainer_ ? trainer_->updates() : 0);
    Report();
    return true;
  } catch (const std::exception& e) {
    const std::string aside = SetAside(path);
    spdlog::warn("graph service: training state not resumed ({}); moved to {}, starting over", e.what(), aside);
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
    if (problem.empty() && !data_) {
      // no shape given (toy worlds in tests): the first valid episode fixes it
      try {
        data_ = std::make_unique<GraphDataset>(GraphDataset::ShapedLike(episode));
        if (data_->num_entities() < 2) {
          data_.reset();
          problem = "fewer than 2 entities";
        }
      } catch (const std::exception& e) {
        problem = e.what();
      }
    }
    if (problem.empty() && data_) problem = data_->Add(episode);
    if (problem.empty()) {
      ++progress_.episodes;
    } else {
      ++progress_.dropped;
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
  data_->Split(config_.held_out_fraction, options_.seed);
  trainer_ = std::make_unique<GnnTrainer>(config_, *data_, options_.seed);
  trainer_->SetContactRadii(options_.contact_radius);
  action_entity_ = SelectActionEntity(*data_);
  action_correlation_ = ActionCorrelations(*data_);
  stable_ = 0;
  Report();
}

void GraphService::UpdateModel() {
  trainer_->Update();
  if (trainer_->skipped_in_a_row() == 0) return;
  progress_.skipped_updates = trainer_->skipped_updates();
  if (trainer_->skipped_in_a_row() == 1)  // once per streak: GnnTrainingDivergedError ends a long one
    spdlog::warn(
        "graph service: GNN update {} skipped: a non-finite loss or an unusable gradient "
        "({} so far; graph.max_skipped_updates_in_a_row: {})",
        trainer_->updates(), trainer_->skipped_updates(), config_.max_skipped_updates_in_a_row);
}

void GraphService::TrainStep() {
  for (int i = 0; i < options_.updates_per_step && trainer_->updates() < config_.max_updates; ++i) {
    UpdateModel();
    if (trainer_->updates() % config_.eval_every_updates == 0) break;  // evaluate at the boundary
  }
  const bool at_eval =
      trainer_->updates() % config_.eval_every_updates == 0 || trainer_->updates() >= config_.max_updates;
  if (!at_eval) return;
  EvaluateGraph();
  const bool stable = stable_ >= config_.stable_evaluations && trainer_->updates() >= config_.min_updates;
  if (stable || trainer_->updates() >= config_.max_updates)
    Finish();
  else
    SaveTraining();
}

void GraphService::EvaluateGraph() {
  // held-out loss and the thresholded graph of the read-out's edge scores
  const EdgeStatistics stats = trainer_->Evaluate();
  const bool cut = config_.readout == config::GraphReadout::kCut;
  const std::vector<double> scores = ReadOutScores(stats, config_, action_entity_);
  LearnedGraph graph =
      AggregateGraph(data_->graph_entities(), scores, cut ? config_.cut_threshold : config_.threshold, action_entity_);
  graph.readout = cut ? "cut" : trainer_->ApartWeights() ? "mean_weight_apart" : "mean_weight";
  graph.mean_weights = stats.mean_weight;
  graph.held_out_loss = stats.held_out_mse;
  graph.updates = trainer_->updates();
  graph.episodes = data_->size();
  graph.action_correlation = action_correlation_;
  const std::vector<uint16_t> kinds = data_->graph_kinds();
  graph.entity_kinds.assign(kinds.begin(), kinds.end());
  // graphs of the warm-up and the KL ramp (edges open or not yet pruned) never count as
  // stable: only evaluations after the full KL weight is reached are compared
  const bool gated = trainer_->Settled();
  stable_ = gated && current_ && SameStructure(current_->graph, graph.graph) ? stable_ + 1 : 0;
  current_ = std::move(graph);
  progress_.updates = trainer_->updates();
  progress_.train_loss = trainer_->last_mse();
  progress_.held_out_loss = stats.held_out_mse;
  progress_.held_out_zero_loss = stats.held_out_zero_mse;
  progress_.entity_loss = stats.held_out_entity_mse;
  progress_.entity_zero_loss = stats.held_out_entity_zero_mse;
  progress_.stable_evaluations = stable_;
  progress_.graph = rl::DescribeGraph(current_->graph);
  progress_.edge_scores = current_->edge_scores;
  progress_.mean_weights = stats.mean_weight;
  Report();
}

void GraphService::Finish() {
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

int GraphService::RefineCapacity() const { return std::max<int>(1, static_cast<int>(data_->train_episodes().size())); }

double GraphService::RefineShare() const {
  return refine_data_
             ? config_.refine_share * std::min(1.0, static_cast<double>(refine_data_->size()) / RefineCapacity())
             : 0.0;
}

void GraphService::StartRefinement() {
  if (options_.refine_episode_steps < config_.window) {
    spdlog::warn("graph service: no refinement: training episodes of {} steps are shorter than a window ({})",
                 options_.refine_episode_steps, config_.window);
    return;
  }
  if (!refine_data_)
    refine_data_ = std::make_unique<GraphDataset>(data_->ForTrainingEpisodes(options_.refine_episode_steps));
  trainer_->SetRefinementData(refine_data_.get(), RefineShare());
  refining_ = true;
  progress_.refining = true;
  spdlog::info("graph service: refining graph v{} from the run's training episodes ({} so far)", published_->version,
               progress_.refine_episodes);
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
    const bool full = refine_data_->size() >= capacity;
    if (problem.empty()) problem = full ? refine_data_->Replace(refine_cursor_, episode) : refine_data_->Add(episode);
    if (!problem.empty()) {
      ++progress_.dropped;
      progress_.last_drop_reason = problem;
      continue;
    }
    if (full) refine_cursor_ = (refine_cursor_ + 1) % capacity;  // the oldest goes next
    ++progress_.refine_episodes;
    ++taken;
    refine_budget_ += config_.refine_updates_per_episode;
    if (progress_.refine_episodes % capacity == 0) {
      // the ring holds a new set of training episodes: every gate is decided again on the
      // mixed data (a closed gate would hardly reopen), and only graphs after the new
      // warm-up and ramp count towards a publication
      trainer_->RestartSchedule();
      refine_decided_ = true;
      stable_ = 0;
      spdlog::info("graph service: {} training episodes in: the edges are decided again (warm-up and KL ramp)",
                   progress_.refine_episodes);
    }
  }
  if (taken > 0) trainer_->SetRefinementData(refine_data_.get(), RefineShare());
  int done = 0;
  while (done < options_.updates_per_step && refine_budget_ > 0) {
    UpdateModel();
    --refine_budget_;
    ++done;
    if (trainer_->updates() % config_.eval_every_updates != 0) continue;
    EvaluateGraph();
    // only graphs of a decision on training episodes, not the drift of the first graph's model
    if (refine_decided_ && !SameStructure(current_->graph, published_->graph) &&
        stable_ >= config_.stable_evaluations) {
      spdlog::info("graph service: the refined graph ({}) differs from v{} ({}) for {} evaluations: publishing v{}",
                   rl::DescribeGraph(current_->graph), published_->version, rl::DescribeGraph(published_->graph),
                   stable_, next_version_);
      PublishCurrent();
    }
    SaveTraining();
    break;
  }
  progress_.updates = trainer_->updates();
  if (taken > 0 || done > 0) Report();
  return taken > 0 || done > 0 ? StepResult::kWorked : StepResult::kIdle;
}

}  // namespace srics::graph_service
