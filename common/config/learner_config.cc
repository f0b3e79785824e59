#include <cmath>

#include "common/config/sections.h"

namespace srics::config {

void ParseLearner(YamlSection s, LearnerConfig* out) {
  s.ReadUint64("replay_capacity", &out->replay_capacity, 1);
  s.ReadUint64("warmup_steps", &out->warmup_steps);
  if (out->warmup_steps > out->replay_capacity)
    s.FailRule("warmup_steps", "must not exceed replay_capacity (" + std::to_string(out->replay_capacity) + ")");
  s.ReadDouble("updates_per_step", &out->updates_per_step, 0, 1e4);
  s.ReadDouble("rate_error_buffer", &out->rate_error_buffer, 1, 1e9);
  s.ReadInt("publish_every_updates", &out->publish_every_updates, 1, 1 << 30);
  s.ReadInt("checkpoint_every_updates", &out->checkpoint_every_updates, 1, 1 << 30);
  s.ReadInt("keep_checkpoints", &out->keep_checkpoints, 1, 100);
  s.ReadInt("max_skipped_updates_in_a_row", &out->max_skipped_updates_in_a_row, 0, 1 << 30);
  s.ReadBool("exploration_into_replay", &out->exploration_into_replay);
  s.ReadInt("threads", &out->threads, 1, 64);
  // recorded in the resolved settings only when given: a run folder made before the key
  // resolves to the same settings, so it resumes on this binary (run_folder_test)
  if (s.Has("precision"))
    s.ReadEnum("precision", &out->precision, {{"fp32", ProductPrecision::kFp32}, {"bf16", ProductPrecision::kBf16}});
  YamlSection relabel = s.Child("relabel");
  RelabelConfig& r = out->relabel;
  relabel.ReadDouble("original", &r.original, 0, 1);
  relabel.ReadDouble("future", &r.future, 0, 1);
  relabel.ReadDouble("sampled", &r.sampled, 0, 1);
  if (std::abs(r.original + r.future + r.sampled - 1.0) > 1e-6)
    relabel.FailRule("sampled", "original + future + sampled must add up to 1");
  relabel.Finish();
  s.Finish();
}

}  // namespace srics::config
