// Issue 15: config values that used to pass or to fail without a useful message. Each error
// names the file, the line, the key and what was expected, and is a ConfigError (the
// launcher's exit code 2), never yaml-cpp's own "bad conversion".

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "common/config/config.h"

#include "tests/common/config/config_files.h"

namespace srics::config {
namespace {

namespace fs = std::filesystem;

class RejectedConfig : public testing::ConfigFiles {
 protected:
  // The ConfigError of loading `file`; fails the test when another exception (or none) came.
  static std::string ErrorOf(const std::string& file, const std::vector<std::string>& overrides = {}) {
    try {
      LoadConfig(file, overrides);
    } catch (const ConfigError& e) {
      return e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a ConfigError: " << e.what();
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  }
};

TEST_F(RejectedConfig, NonScalarKeyNamesFileLineAndWhereItIs) {
  // a list as a key (a flow sequence before the colon) and a mapping as a key
  const std::string list_key = Write("list-key.yaml", "run:\n  name: x\ntransport:\n  [domain_id, run_id]: 5\n");
  EXPECT_EQ(ErrorOf(list_key), list_key +
                                   ":4: transport: expected a plain key (a name such as 'domain_id'), "
                                   "got a list as a key");
  const std::string map_key = Write("map-key.yaml", "actors:\n  count: 2\n  ? {a: 1}\n  : 3\n");
  EXPECT_EQ(ErrorOf(map_key), map_key +
                                  ":3: actors: expected a plain key (a name such as 'domain_id'), "
                                  "got a mapping as a key");
  // nothing as a key, at the top level
  const std::string null_key = Write("null-key.yaml", "run:\n  name: x\n~: 3\n");
  EXPECT_EQ(ErrorOf(null_key), null_key +
                                   ":3: <top>: expected a plain key (a name such as 'domain_id'), "
                                   "got nothing as a key");
  // through extends: the base file is named
  const std::string base = Write("base.yaml", "learner:\n  relabel:\n    [x]: 1\n");
  const std::string top = Write("top.yaml", "extends: base.yaml\nrun:\n  name: y\n");
  EXPECT_EQ(ErrorOf(top), base +
                              ":3: learner.relabel: expected a plain key (a name such as 'domain_id'), "
                              "got a list as a key");
  // and on the command line
  const std::string fine = Write("fine.yaml", "run:\n  name: z\n");
  EXPECT_EQ(ErrorOf(fine, {"env={[a]: 1}"}),
            "command line: env: expected a plain key (a name such as 'domain_id'), got a list as a key");
}

TEST_F(RejectedConfig, NonScalarKeyInParsedTextToo) {
  try {
    ParseConfig("graph:\n  {a: 1}: 2\n", "inline.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "inline.yaml:2: graph: expected a plain key (a name such as 'domain_id'), got a mapping as a key");
  }
}

TEST_F(RejectedConfig, ZeroEvaluationPeriodIsRefused) {
  // 0 made an evaluating actor loop forever looking for its next evaluation
  const std::string file = Write("eval.yaml", "actors:\n  evaluators: 1\n  eval_every_env_steps: 0\n");
  EXPECT_EQ(ErrorOf(file), file + ":3: actors.eval_every_env_steps: expected a positive integer, got '0'");
}

TEST_F(RejectedConfig, OtherZeroSizesPeriodsAndRates) {
  const struct {
    const char* yaml;
    const char* message;
  } cases[] = {
      {"run:\n  total_env_steps: 0\n", ":2: run.total_env_steps: expected a positive integer, got '0'"},
      {"learner:\n  replay_capacity: 0\n", ":2: learner.replay_capacity: expected a positive integer, got '0'"},
      {"learner:\n  keep_checkpoints: 0\n", ":2: learner.keep_checkpoints: expected an integer in [1, 100], got '0'"},
      {"learner:\n  checkpoint_every_updates: 0\n", ":2: learner.checkpoint_every_updates: expected an integer in"},
      {"learner:\n  publish_every_updates: -1\n", ":2: learner.publish_every_updates: expected an integer in"},
      {"agent:\n  sac:\n    q_lr: 0\n", ":3: agent.sac.q_lr: expected a number in [1e-12, 1], got '0'"},
      {"graph:\n  learning_rate: 0\n", ":2: graph.learning_rate: expected a number in [1e-12, 1], got '0'"},
      {"env:\n  physics:\n    static_objects: glued\n",
       ":3: env.physics.static_objects: expected one of 'put_back' 'fixed', got 'glued'"},
      {"graph:\n  object_contact_margin_m: -0.01\n",
       ":2: graph.object_contact_margin_m: expected a number in [0, 1], got '-0.01'"},
      {"graph:\n  object_pair_share: 2\n", ":2: graph.object_pair_share: expected a number in [0, 1], got '2'"},
      {"transport:\n  status_period_s: 0\n", ":2: transport.status_period_s: expected a number in [0.01, 3600]"},
      {"transport:\n  episode_batch_ms: -1\n", ":2: transport.episode_batch_ms: expected an integer in [0, 10000]"},
  };
  for (const auto& c : cases) {
    const std::string file = Write("case.yaml", c.yaml);
    const std::string message = ErrorOf(file);
    EXPECT_EQ(message.rfind(file + c.message, 0), 0u) << c.yaml << " gave: " << message;
  }
}

TEST_F(RejectedConfig, RefinementNeedsALearnedGraphAndWindowsThatFitTrainingEpisodes) {
  const std::string fixed = Write("fixed.yaml", "graph:\n  ground_truth: true\n  refine_after_publish: true\n");
  EXPECT_NE(ErrorOf(fixed).find("graph.refine_after_publish: needs a learned graph"), std::string::npos)
      << ErrorOf(fixed);
  const std::string no_share = Write("share.yaml", "graph:\n  refine_after_publish: true\n  refine_share: 0\n");
  EXPECT_NE(ErrorOf(no_share).find("needs refine_share and refine_updates_per_episode above 0"), std::string::npos);
  // windows of 20 steps do not fit training episodes of 10
  const std::string windows =
      Write("windows.yaml", "graph:\n  refine_after_publish: true\n  window: 20\nactors:\n  train_episode_steps: 10\n");
  EXPECT_NE(
      ErrorOf(windows).find("graph.window: must not exceed actors.train_episode_steps (10) with refine_after_publish"),
      std::string::npos)
      << ErrorOf(windows);
  // the same without refinement is fine
  EXPECT_NO_THROW(LoadConfig(windows, {"graph.refine_after_publish=false"}));
}

// HAC ignores chains of training episodes (its levels start each from a reset): refused, not
// silently dropped; the other methods take them
TEST_F(RejectedConfig, ChainedTrainingEpisodesAreRefusedForHac) {
  const std::string hac = Write("hac.yaml", "run:\n  method: hac\nactors:\n  train_chain_episodes: 9\n");
  EXPECT_NE(ErrorOf(hac).find("actors.train_chain_episodes: must be 1 with run.method hac"), std::string::npos)
      << ErrorOf(hac);
  EXPECT_NO_THROW(LoadConfig(hac, {"run.method=srics"}));
  EXPECT_NO_THROW(LoadConfig(hac, {"actors.train_chain_episodes=1"}));
}

TEST_F(RejectedConfig, KeepCheckpointsDefaultsToThree) {
  EXPECT_EQ(LoadConfig(Write("empty.yaml", "")).learner.keep_checkpoints, 3);
  EXPECT_EQ(LoadConfig(Write("one.yaml", "learner:\n  keep_checkpoints: 1\n")).learner.keep_checkpoints, 1);
}

// Issue 39: eight levels of anchors, each a list of nine aliases of the level before, expanded
// to 9^8 nodes when the tree was walked and merged: 300 bytes took 3.9 GB and died with
// bad_alloc. Refused now before a node is built, in well under a second.
std::string AnchorBomb() {
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level <= 8; ++level) {
    const std::string before = "*a" + std::to_string(level - 1);
    text += "a" + std::to_string(level) + ": &a" + std::to_string(level) + " [";
    for (int i = 0; i < 9; ++i) text += (i ? "," : "") + before;
    text += "]\n";
  }
  return text + "run:\n  name: bomb\n";
}

TEST_F(RejectedConfig, AnchorBombIsRefusedInUnderASecondNamingAnchors) {
  const std::string bomb = Write("bomb.yaml", AnchorBomb());
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(ErrorOf(bomb), bomb +
                               ":1: an anchor (&name): anchors and aliases are not accepted in a config; "
                               "write the values out");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  // the same text given as a config's text (a resolved-config from elsewhere, the fuzzer)
  try {
    ParseConfig(AnchorBomb(), "sent.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("sent.yaml:1: an anchor"), std::string::npos) << e.what();
  }
  // an alias alone (its anchor in a base file would be unknown here) and an anchor in an override
  EXPECT_NE(ErrorOf(Write("alias.yaml", "run:\n  name: *base\n")).find("not valid YAML"), std::string::npos);
  EXPECT_EQ(ErrorOf(Write("plain.yaml", "run:\n  name: x\n"), {"run.name=&n y"}),
            "command line: run.name:1: an anchor (&name): anchors and aliases are not accepted in a config; "
            "write the values out");
}

TEST_F(RejectedConfig, TooManyNodesTooDeepOrTooLargeIsRefusedNamingTheLimit) {
  std::string flat = "env:\n  objects: [";
  for (int i = 0; i <= 100000; ++i) flat += i ? ",0" : "0";
  const std::string many = Write("many.yaml", flat + "]\n");
  EXPECT_NE(ErrorOf(many).find(many + ":2: more than 100000 YAML nodes"), std::string::npos) << ErrorOf(many);
  const std::string deep = Write("deep.yaml", "run: " + std::string(100, '[') + std::string(100, ']') + "\n");
  EXPECT_NE(ErrorOf(deep).find(deep + ":1: nested deeper than 64 levels"), std::string::npos) << ErrorOf(deep);
  const std::string big = Write("big.yaml", "run:\n  name: x\n#" + std::string(size_t{1} << 20, 'x') + "\n");
  EXPECT_NE(
      ErrorOf(big).find(big + ": " + std::to_string(fs::file_size(big)) + " bytes, over the limit of 1048576 bytes"),
      std::string::npos)
      << ErrorOf(big);
  // the shipped configs are far inside every limit
  EXPECT_NO_THROW(LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/campaign/relational-4-750k.yaml"));
}

// Issue 34: the reference's starting values are options; a starting std outside the clamp is refused.
TEST_F(RejectedConfig, InitialPolicyStdMustLieInsideTheLogStdClamp) {
  const std::string tiny = Write("tiny.yaml", "agent:\n  network:\n    initial_policy_std: 1.0e-12\n");
  EXPECT_NE(ErrorOf(tiny).find("agent.network.initial_policy_std: its log must lie in [log_std_min, log_std_max]"),
            std::string::npos)
      << ErrorOf(tiny);
  const Config reference =
      LoadConfig(Write("ok.yaml", "agent:\n  network:\n    initial_policy_std: 0.2\n    hidden_bias: 0.1\n"));
  EXPECT_DOUBLE_EQ(reference.agent.network.initial_policy_std, 0.2);
  EXPECT_DOUBLE_EQ(reference.agent.network.hidden_bias, 0.1);
  EXPECT_EQ(LoadConfig(Write("none.yaml", "")).agent.network.initial_policy_std, 0.0);  // off by default
}

}  // namespace
}  // namespace srics::config
