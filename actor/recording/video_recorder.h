#pragma once
// actors.record_eval_episodes: the first K episodes of every evaluation of a trained policy
// drawn by MuJoCo's offscreen renderer into <run folder>/eval/episode-NNNNNN.gif (PNG frames
// in episode-NNNNNN/ without ffmpeg), one row each in eval/recorded.csv. The web dashboard
// shows the newest; `srics eval` writes its own episodes beside them.
//
//   loop.set_eval_recorder(MakeVideoRecorder(loop.environment(), {.dir = run_dir + "/eval", ...}));
//
// NNNNNN = (policy version mod 10000) * 100 + (actor id mod 10) * 10 + episode: one name per
// recorded episode of a run of up to 10000 policy versions. The GL context is made at the first
// recorded episode; when this machine cannot render, a warning says why and nothing is recorded
// (the evaluation itself is unaffected).

#include <cstdint>
#include <memory>
#include <string>

#include "actor/env/environment.h"
#include "actor/eval_episode.h"
#include "common/config/config.h"

namespace srics::actor {

struct VideoRecorderOptions {
  std::string dir;   // the run folder's eval/ (created)
  int episodes = 1;  // recorded per evaluation (the first ones)
  uint32_t actor_id = 0;
  int width = 320, height = 240;
  int fps = 10;
};

// Throws std::invalid_argument when `env` is not a rearrange environment (nothing to draw).
std::unique_ptr<EvalRecorder> MakeVideoRecorder(env::Environment& env, const VideoRecorderOptions& options);

// The recorder a run's actor gets from its config: null unless actors.record_eval_episodes > 0,
// the actor evaluates (actors.evaluators) and there is a run folder.
std::unique_ptr<EvalRecorder> RecorderFor(const config::Config& config, env::Environment& env, uint32_t actor_id,
                                          const std::string& run_dir);

// The file name (without extension) of a recorded episode.
std::string RecordedEpisodeName(uint64_t policy_version, uint32_t actor_id, int episode);

}  // namespace srics::actor
