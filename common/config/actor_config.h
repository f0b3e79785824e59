#pragma once
// Actor processes: how many, episode lengths, evaluation schedule.

#include <cstdint>

namespace srics::config {

// Which subgoal each evaluation attempt pursues (rl::EvaluationProtocol says how).
enum class EvalSchedule {
  kReference,         // the paper's and the reference code's: 2N - 1 attempts (9 on 4 objects)
  kIndependentDraws,  // the campaign's runs to 2026-12-04
};

struct ActorConfig {
  int count = 2;                   // actor processes started by the launcher
  int explore_episode_steps = 50;  // random-action episodes until graph + weights exist
  // Exploration for the graph's data (not in the paper: uniformly random actions only). This
  // share of explore episodes is driven by a pushing controller: every
  // explore_push_segment_steps it picks a random object and a random target in the subgoal box
  // and pushes the object toward it (env::PushAction) with Gaussian action noise. Random
  // actions touch objects in ~10% of the steps and seldom drag a tied object far enough for
  // its partner to follow; pushes do both often.
  double explore_push_fraction = 0.0;
  int explore_push_segment_steps = 10;
  double explore_push_noise = 0.3;  // std of the noise added to each action component
  int train_episode_steps = 20;     // one subgoal per episode
  // Training episodes per reset of the table (not in the paper: 1, every episode starts from a
  // reset). With N > 1 the next N - 1 episodes start where the one before left the table, as an
  // evaluation's attempts do: start states like an evaluation's (pucks where earlier pushes
  // left them, the hand beside them), each episode with a new subgoal drawn as usual. Training
  // never sees other objects' goals (the selectivity term charges their motion wherever they
  // are), so this changes where training starts, not what it rewards (docs/results.md, "The
  // paper's budget"). An evaluation, an explore episode or an unstable one ends a chain; 1 with
  // HAC. Recorded in a run's resolved-config.yaml only when given (runs started before it
  // resume unchanged).
  int train_chain_episodes = 1;
  int eval_attempt_steps = 20;  // steps per subgoal attempt at evaluation
  EvalSchedule eval_schedule = EvalSchedule::kReference;
  int evaluators = 1;                     // actors 0..evaluators-1 also evaluate
  uint64_t eval_every_env_steps = 10000;  // per evaluating actor
  int eval_episodes = 10;                 // episodes per evaluation
  // the first K episodes of every evaluation of a trained policy are drawn into the run
  // folder's eval/ (GIF with ffmpeg, else PNG frames), for people and the web dashboard; 0 =
  // none. Software rendering costs ~1-2 s per episode here
  int record_eval_episodes = 0;
  int record_width = 320;  // pixels, even
  int record_height = 240;
};

}  // namespace srics::config
