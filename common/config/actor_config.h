#pragma once
// Actor processes: how many, episode lengths, evaluation schedule.

#include <cstdint>

namespace srics::config {

struct ActorConfig {
  int count = 2;                       // actor processes started by the launcher
  int explore_episode_steps = 50;      // random-action episodes until graph + weights exist
  int train_episode_steps = 20;        // one subgoal per episode
  int eval_attempt_steps = 20;         // steps per subgoal attempt at evaluation
  int evaluators = 1;                  // actors 0..evaluators-1 also evaluate
  uint64_t eval_every_env_steps = 10000;  // per evaluating actor
  int eval_episodes = 10;              // episodes per evaluation
};

}  // namespace srics::config
