#include "graph_service/service.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <stdexcept>

#include "common/rl/graph.h"

namespace srics::graph {

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

GraphService::GraphService(const config::GraphConfig& config, const ServiceOptions& options,
                           EpisodeSource* source, GraphSink* sink, ProgressCallback on_progress)
    : config_(config), options_(options), source_(source), sink_(sink),
      on_progress_(std::move(on_progress)) {
  if (source_ == nullptr || sink_ == nullptr)
    throw std::invalid_argument("GraphService: source and sink are required");
  progress_.target_episodes = config_.episodes;
}

std::string GraphService::graph_path() const {
  return options_.state_dir.empty() ? "" : options_.state_dir + "/graph.json";
}

void GraphService::Report() {
  progress_.elapsed_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (on_progress_) on_progress_(progress_);
}

int GraphService::Run(const std::atomic<bool>& stop) {
  start_ = std::chrono::steady_clock::now();
  progress_.phase = Progress::Phase::kLoading;
  Report();
  if (LoadSaved()) return 0;
  if (!Collect(stop) || !Train(stop)) {
    progress_.phase = Progress::Phase::kStopped;
    Report();
    return 1;
  }
  Finish();
  return 0;
}

bool GraphService::LoadSaved() {
  const std::string path = graph_path();
  if (path.empty() || !std::filesystem::exists(path)) return false;
  try {
    LearnedGraph saved = LoadGraph(path);
    spdlog::info("graph service: re-publishing saved graph version {} ({}) from {}",
                 saved.version, rl::DescribeGraph(saved.graph), path);
    sink_->Publish(saved);
    progress_.phase = Progress::Phase::kPublished;
    progress_.published_version = saved.version;
    progress_.graph = rl::DescribeGraph(saved.graph);
    progress_.mean_weights = saved.mean_weights;
    progress_.held_out_loss = saved.held_out_loss;
    progress_.updates = saved.updates;
    progress_.episodes = saved.episodes;
    published_ = std::move(saved);
    Report();
    return true;
  } catch (const std::exception& e) {
    // an unusable file is kept aside for inspection and the graph is learned again
    const std::string aside = path + ".rejected";
    std::error_code ec;
    std::filesystem::rename(path, aside, ec);
    spdlog::warn("graph service: saved graph rejected ({}); moved to {}, learning again",
                 e.what(), aside);
    return false;
  }
}

bool GraphService::Collect(const std::atomic<bool>& stop) {
  progress_.phase = Progress::Phase::kCollecting;
  Report();
  std::vector<rl::Episode> batch;
  auto last_report = std::chrono::steady_clock::now();
  while (!stop.load()) {
    batch.clear();
    const bool open = source_->Poll(options_.poll_timeout, &batch);
    for (const rl::Episode& episode : batch) {
      if (progress_.episodes >= config_.episodes) break;
      std::string problem;
      if (episode.mode != rl::EpisodeMode::kExplore) continue;  // other modes are not ours
      if (episode.num_steps != config_.episode_steps) {
        problem = "episode has " + std::to_string(episode.num_steps) + " steps, expected " +
                  std::to_string(config_.episode_steps);
      } else if (!data_) {
        // the first valid episode fixes the data set's layout
        problem = rl::ValidateEpisode(episode);
        if (problem.empty()) {
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
      }
      if (problem.empty() && data_) problem = data_->Add(episode);
      if (problem.empty()) {
        ++progress_.episodes;
      } else {
        ++progress_.dropped;
        progress_.last_drop_reason = problem;
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (progress_.episodes >= config_.episodes) {
      Report();
      return true;
    }
    if (now - last_report > std::chrono::seconds(1)) {
      Report();
      last_report = now;
    }
    if (!open) {
      spdlog::warn("graph service: episode source closed after {} of {} episodes",
                   progress_.episodes, config_.episodes);
      return false;
    }
  }
  return false;
}

bool GraphService::Train(const std::atomic<bool>& stop) {
  progress_.phase = Progress::Phase::kTraining;
  data_->Split(config_.held_out_fraction, options_.seed);
  trainer_ = std::make_unique<GnnTrainer>(config_, *data_, options_.seed);
  const int action_entity = SelectActionEntity(*data_);
  const std::vector<double> correlation = ActionCorrelations(*data_);
  int stable = 0;
  while (trainer_->updates() < config_.max_updates) {
    for (int i = 0; i < config_.eval_every_updates && trainer_->updates() < config_.max_updates;
         ++i) {
      if (stop.load()) return false;
      trainer_->Update();
    }
    // evaluation: held-out loss and the thresholded graph of the mean weights
    const EdgeStatistics stats = trainer_->Evaluate();
    LearnedGraph graph = AggregateGraph(data_->num_entities(), stats.mean_weight,
                                        config_.threshold, action_entity);
    graph.held_out_loss = stats.held_out_mse;
    graph.updates = trainer_->updates();
    graph.episodes = data_->size();
    graph.action_correlation = correlation;
    graph.entity_kinds.assign(data_->entity_kinds().begin(), data_->entity_kinds().end());
    // graphs of the warm-up and the KL ramp (edges open or not yet pruned) never count as
    // stable: only evaluations after the full KL weight is reached are compared
    const bool gated =
        trainer_->updates() > static_cast<int64_t>(config_.warmup_updates) + config_.kl_ramp_updates;
    stable = gated && current_ && SameStructure(current_->graph, graph.graph) ? stable + 1 : 0;
    current_ = std::move(graph);
    progress_.updates = trainer_->updates();
    progress_.train_loss = trainer_->last_mse();
    progress_.held_out_loss = stats.held_out_mse;
    progress_.held_out_zero_loss = stats.held_out_zero_mse;
    progress_.entity_loss = stats.held_out_entity_mse;
    progress_.entity_zero_loss = stats.held_out_entity_zero_mse;
    progress_.stable_evaluations = stable;
    progress_.graph = rl::DescribeGraph(current_->graph);
    progress_.mean_weights = stats.mean_weight;
    Report();
    if (stable >= config_.stable_evaluations && trainer_->updates() >= config_.min_updates) break;
  }
  return true;
}

void GraphService::Finish() {
  LearnedGraph graph = *current_;
  graph.version = next_version_++;
  if (!options_.state_dir.empty()) {
    std::filesystem::create_directories(options_.state_dir);
    try {
      if (options_.render_pictures) {
        const std::string missing =
            SaveGraphWithPictures(graph, options_.state_dir + "/graph");
        if (!missing.empty()) spdlog::warn("graph service: could not render {}", missing);
      } else {
        SaveGraph(graph, graph_path());
      }
    } catch (const std::exception& e) {
      spdlog::error("graph service: saving the graph failed: {}", e.what());
    }
  }
  sink_->Publish(graph);
  progress_.phase = Progress::Phase::kPublished;
  progress_.published_version = graph.version;
  published_ = std::move(graph);
  Report();
}

}  // namespace srics::graph
