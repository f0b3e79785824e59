#pragma once
// The episode loops' options a run's config implies (episode lengths, full goal for SAC+HER and
// HAC, HAC's levels, the subgoal order by method: depth for SRICS and its selectivity ablation,
// random otherwise; the explore pushes' geometry): the one place where the loops meet the config.

#include "actor/eval_episode.h"
#include "actor/explore_episode.h"
#include "actor/hac_acting.h"
#include "actor/train_episode.h"
#include "common/config/config.h"
#include "common/rl/agent_shape.h"

namespace srics::actor {

ExploreOptions ExploreOptionsFor(const config::Config& config);
HacActOptions HacActOptionsFor(const config::Config& config, const rl::RunShape& shape);
TrainOptions TrainOptionsFor(const config::Config& config, const rl::RunShape& shape);
EvalOptions EvalOptionsFor(const config::Config& config, const rl::RunShape& shape);

}  // namespace srics::actor
