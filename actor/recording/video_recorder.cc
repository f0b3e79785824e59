#include "actor/recording/video_recorder.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "actor/env/rearrange_env.h"
#include "actor/env/render/episode_renderer.h"
#include "actor/env/render/gl_context.h"
#include "actor/env/render/video_writer.h"

namespace srics::actor {
namespace {

namespace fs = std::filesystem;

std::string EntityName(int entity) { return entity == 0 ? "arm" : "object " + std::to_string(entity); }

class VideoRecorder : public EvalRecorder, public EvalEpisodeObserver {
 public:
  VideoRecorder(env::RearrangeEnv& env, const VideoRecorderOptions& options) : env_(env), options_(options) {
    render_.width = options.width;
    render_.height = options.height;
    env::CheckRenderOptions(render_);
    video_.fps = options.fps;
  }

  EvalEpisodeObserver* Begin(uint64_t policy_version, int episode, uint64_t seed) override {
    if (episode >= options_.episodes || disabled_ || !Ready()) return nullptr;
    name_ = RecordedEpisodeName(policy_version, options_.actor_id, episode);
    version_ = policy_version;
    seed_ = seed;
    const std::string file =
        name_ + (video_.format == env::VideoFormat::kPng ? "" : "." + env::VideoExtension(video_.format));
    try {
      writer_.emplace((fs::path(options_.dir) / file).string(), render_.width, render_.height, video_);
    } catch (const std::exception& e) {
      Disable(e.what());
      return nullptr;
    }
    file_ = file;
    caption_ = "policy v" + std::to_string(policy_version) + "  episode " + std::to_string(episode);
    return this;
  }

  void OnState(const env::Environment& env, int entity) override {
    if (!writer_) return;
    const std::string what = env.steps() == 0 ? "start" : entity < 0 ? "full goal" : "subgoal: " + EntityName(entity);
    try {
      writer_->Write(
          renderer_->Render(entity, caption_ + "  step " + std::to_string(env.steps()) + "  " + what).rgb.data());
    } catch (const std::exception& e) {
      writer_.reset();
      Disable(e.what());
    }
  }

  void End(const std::optional<rl::EpisodeMetrics>& metrics, int steps) override {
    if (!writer_) return;
    int frames = 0;
    try {
      writer_->Close();
      frames = writer_->frames();
    } catch (const std::exception& e) {
      writer_.reset();
      Disable(e.what());
      return;
    }
    writer_.reset();
    // one row per recorded episode, for the dashboard's caption and for people
    const fs::path csv = fs::path(options_.dir) / "recorded.csv";
    const bool fresh = !fs::exists(csv);
    std::ofstream out(csv, std::ios::app);
    if (fresh)
      out << "policy_version,actor_id,seed,status,steps,frames,avg_distance,avg_object_distance,success,selectivity,"
             "video\n";
    out << version_ << "," << options_.actor_id << "," << seed_ << "," << (metrics ? "ok" : "unstable") << "," << steps
        << "," << frames;
    if (metrics)
      out << "," << metrics->avg_distance << "," << metrics->avg_object_distance << "," << (metrics->success ? 1 : 0)
          << "," << metrics->selectivity;
    else
      out << ",,,,";
    out << "," << file_ << "\n";
    if (!out) spdlog::warn("recording evaluation episodes: cannot write {}", csv.string());
  }

 private:
  // The GL context and renderer at the first recorded episode (an actor that never records
  // never touches OpenGL).
  bool Ready() {
    if (renderer_) return true;
    try {
      fs::create_directories(options_.dir);
      if (!env::FfmpegAvailable())
        video_.format = env::VideoFormat::kPng;
      else
        video_.format = env::VideoFormat::kGif;
      gl_.emplace();
      renderer_.emplace(env_, *gl_, render_);
      spdlog::info("recording {} evaluation episode(s) per evaluation into {} ({}, {})", options_.episodes,
                   options_.dir, env::VideoExtension(video_.format), gl_->description());
      return true;
    } catch (const std::exception& e) {
      Disable(e.what());
      return false;
    }
  }

  void Disable(const std::string& why) {
    disabled_ = true;
    renderer_.reset();
    gl_.reset();
    spdlog::warn("recording evaluation episodes stopped: {} (the evaluations go on)", why);
  }

  env::RearrangeEnv& env_;
  VideoRecorderOptions options_;
  env::RenderOptions render_;
  env::VideoOptions video_;
  std::optional<env::GlContext> gl_;
  std::optional<env::EpisodeRenderer> renderer_;
  std::optional<env::VideoWriter> writer_;
  bool disabled_ = false;
  std::string name_, file_, caption_;
  uint64_t version_ = 0, seed_ = 0;
};

}  // namespace

std::string RecordedEpisodeName(uint64_t policy_version, uint32_t actor_id, int episode) {
  char name[32];
  std::snprintf(name, sizeof name, "episode-%06llu",
                static_cast<unsigned long long>((policy_version % 10000) * 100 + (actor_id % 10) * 10 + episode % 10));
  return name;
}

std::unique_ptr<EvalRecorder> RecorderFor(const config::Config& config, env::Environment& env, uint32_t actor_id,
                                          const std::string& run_dir) {
  const config::ActorConfig& a = config.actors;
  if (a.record_eval_episodes <= 0 || run_dir.empty() || static_cast<int>(actor_id) >= a.evaluators) return nullptr;
  return MakeVideoRecorder(env, {.dir = (fs::path(run_dir) / "eval").string(),
                                 .episodes = a.record_eval_episodes,
                                 .actor_id = actor_id,
                                 .width = a.record_width,
                                 .height = a.record_height});
}

std::unique_ptr<EvalRecorder> MakeVideoRecorder(env::Environment& env, const VideoRecorderOptions& options) {
  auto* rearrange = dynamic_cast<env::RearrangeEnv*>(&env);
  if (rearrange == nullptr) throw std::invalid_argument("recording evaluation episodes: not a rearrange environment");
  return std::make_unique<VideoRecorder>(*rearrange, options);
}

}  // namespace srics::actor
