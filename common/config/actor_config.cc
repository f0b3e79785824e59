#include "common/config/sections.h"

namespace srics::config {

void ParseActors(YamlSection s, ActorConfig* out) {
  s.ReadInt("count", &out->count, 0, 1024);
  s.ReadInt("explore_episode_steps", &out->explore_episode_steps, 1, 100000);
  s.ReadDouble("explore_push_fraction", &out->explore_push_fraction, 0, 1);
  s.ReadInt("explore_push_segment_steps", &out->explore_push_segment_steps, 1, 100000);
  s.ReadDouble("explore_push_noise", &out->explore_push_noise, 0, 10);
  s.ReadInt("train_episode_steps", &out->train_episode_steps, 1, 100000);
  if (s.Has("train_chain_episodes")) s.ReadInt("train_chain_episodes", &out->train_chain_episodes, 1, 1000);
  s.ReadInt("eval_attempt_steps", &out->eval_attempt_steps, 1, 100000);
  s.ReadEnum<EvalSchedule>(
      "eval_schedule", &out->eval_schedule,
      {{"reference", EvalSchedule::kReference}, {"independent_draws", EvalSchedule::kIndependentDraws}});
  s.ReadInt("evaluators", &out->evaluators, 0, 1024);
  s.ReadUint64("eval_every_env_steps", &out->eval_every_env_steps, 1);
  s.ReadInt("eval_episodes", &out->eval_episodes, 1, 100000);
  s.ReadInt("record_eval_episodes", &out->record_eval_episodes, 0, 10);
  s.ReadInt("record_width", &out->record_width, 16, 4096);
  s.ReadInt("record_height", &out->record_height, 16, 4096);
  if (out->record_width % 2 != 0) s.Fail("record_width", "an even number of pixels (video encoders need it)");
  if (out->record_height % 2 != 0) s.Fail("record_height", "an even number of pixels (video encoders need it)");
  if (out->evaluators > out->count && out->count > 0)
    s.FailRule("evaluators", "cannot exceed count (" + std::to_string(out->count) + ")");
  s.Finish();
}

}  // namespace srics::config
