// srics-draw-episode: runs one episode of a rearrange environment and draws it from above.
//
//   srics-draw-episode --config deploy/configs/env/relational-4.yaml --seed 3
//       --policy push --steps 100 --out episode.png
//
// Policies: "push" (scripted: pushes each object to its goal in turn, then returns the hand)
// or "random" (uniform actions, as in the exploration phase).

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "actor/env/episode_drawing.h"
#include "actor/env/metrics.h"
#include "actor/env/rearrange_env.h"
#include "actor/env/scripted_policy.h"
#include "common/cli/cli.h"
#include "common/config/config.h"
#include "common/config/config_error.h"

namespace {

struct Args {
  std::string config = "deploy/configs/env/rearrange-3.yaml";
  std::vector<std::string> overrides;
  uint64_t seed = 0;
  int steps = 100;
  std::string policy = "push";
  std::string out = "episode.png";
  bool eval = false;
};

// Parses the command line into *a: nothing when the program goes on, else its exit code (0
// after --help or --version, 2 for a bad argument).
std::optional<int> Parse(int argc, char** argv, Args* a) {
  CLI::App app{"runs one episode of a rearrange environment and draws it from above", "srics-draw-episode"};
  srics::cli::Configure(app);
  app.add_option("--config", a->config, "an environment preset or run config");
  app.add_option("--set", a->overrides, "override a config value")
      ->allow_extra_args(false)
      ->type_name("K=V")
      ->default_str("");
  app.add_option("--seed", a->seed, "the episode's seed (initial state and goals)")->check(srics::cli::Integer(0));
  app.add_option("--steps", a->steps, "env steps")->check(srics::cli::Integer(1, 100000));
  app.add_option("--policy", a->policy,
                 "push (scripted: pushes each object to its goal in turn, then returns the hand) or random")
      ->check(CLI::IsMember({"push", "random"}));
  app.add_flag("--eval", a->eval, "the evaluation split of initial states and goals");
  app.add_option("--out", a->out, "the picture: FILE.png or FILE.svg");
  if (const auto code = srics::cli::Parse(app, argc, argv)) return code;
  a->config = srics::cli::FindConfig(a->config);  // the default too, when installed
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace srics;
  Args args;
  if (const auto code = Parse(argc, argv, &args)) return *code;
  try {
    const config::Config cfg = config::LoadConfig(args.config, args.overrides);
    env::RearrangeEnv environment(cfg.env);
    environment.Reset(args.seed, args.eval ? env::Split::kEval : env::Split::kTrain);
    const auto objects = config::EffectiveObjects(cfg.env);

    env::EpisodeTrace trace;
    trace.config = cfg.env;
    trace.present = environment.present();
    trace.goals = environment.goals();
    trace.positions.push_back(environment.Positions());
    env::Rng rng(args.seed ^ 0x9e3779b97f4a7c15ULL);
    for (int t = 0; t < args.steps; ++t) {
      const auto pos = environment.Positions();
      env::Vec2 action{0, 0};
      if (args.policy == "random") {
        action = {env::Uniform(rng, -1, 1), env::Uniform(rng, -1, 1)};
      } else {
        // the first movable object away from its goal, else the hand home
        const auto home = env::ReachAction(pos[0], trace.goals[0], cfg.env.hand.action_scale);
        action = {0.3 * home[0], 0.3 * home[1]};
        for (size_t k = 1; k < pos.size(); ++k) {
          const auto& o = objects[trace.present[k - 1] - 1];
          const double d = std::hypot(pos[k][0] - trace.goals[k][0], pos[k][1] - trace.goals[k][1]);
          const env::PushGeometry g = env::MakePushGeometry(cfg.env, trace.present[k - 1]);
          if (o.is_static || d < 2 * g.done_tolerance) continue;
          action = env::PushAction(pos[0], pos[k], trace.goals[k], g);
          break;
        }
      }
      if (environment.Step(action) == env::StepStatus::kUnstable) {
        std::fprintf(stderr, "unstable step %d: episode ended\n", t);
        break;
      }
      trace.positions.push_back(environment.Positions());
    }
    const env::Metrics m = environment.ComputeMetrics();
    char title[256];
    std::snprintf(title, sizeof(title), "%s seed %llu, %s policy, %d steps: avg distance %.3f, success %d",
                  args.config.c_str(), static_cast<unsigned long long>(args.seed), args.policy.c_str(),
                  environment.steps(), m.avg_distance, m.success ? 1 : 0);
    trace.title = title;
    env::DrawEpisode(trace, args.out);
    std::printf("%s\nwrote %s\n", title, args.out.c_str());
    return 0;
  } catch (const config::ConfigError& e) {  // names the file, line and key
    std::fprintf(stderr, "srics-draw-episode: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "srics-draw-episode: %s\n", e.what());
    return 1;
  }
}
