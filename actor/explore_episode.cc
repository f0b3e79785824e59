#include "actor/explore_episode.h"

#include <algorithm>
#include <random>
#include <vector>

#include "actor/episode_parts.h"

namespace srics::actor {

std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed, nn::Rng& rng) {
  ExploreOptions options;
  options.steps = steps;
  return RunExploreEpisode(env, options, seed, rng);
}

std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, const ExploreOptions& options, uint64_t seed,
                                             nn::Rng& rng) {
  env.Reset(seed);
  Observer observer(env);
  rl::Episode episode = StartEpisode(env, observer.layout());
  episode.mode = rl::EpisodeMode::kExplore;
  episode.num_steps = options.steps;
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::normal_distribution<double> noise(0.0, options.push_noise);
  // drawn only when pushes are on, so that random-only runs keep their random streams
  const bool push =
      options.push_fraction > 0 && std::uniform_real_distribution<double>(0, 1)(rng) < options.push_fraction;
  const int objects = env.layout().num_entities - 1;
  std::vector<float> action(env.action_dim());
  observer.Observe(env);
  observer.Append(&episode.states);
  int object = 1;
  env::Vec2 target{};
  for (int t = 0; t < options.steps; ++t) {
    if (push && objects > 0 && action.size() == 2) {
      if (t % options.push_segment_steps == 0) {
        object = 1 + static_cast<int>(std::uniform_int_distribution<int>(0, objects - 1)(rng));
        for (int a = 0; a < 2; ++a)
          target[a] = std::uniform_real_distribution<double>(options.target_low[a], options.target_high[a])(rng);
      }
      const std::vector<env::Vec2> at = env.Positions();
      const env::Vec2 act = env::PushAction(at[0], at[object], target, options.push);
      for (int a = 0; a < 2; ++a) action[a] = static_cast<float>(std::clamp(act[a] + noise(rng), -1.0, 1.0));
    } else {
      for (float& a : action) a = uniform(rng);
    }
    if (!StepWith(env, action.data(), env.action_dim(), &episode.actions)) return std::nullopt;
    observer.Observe(env);
    observer.Append(&episode.states);
  }
  return episode;
}

}  // namespace srics::actor
