// Issue 15: config values that used to pass or to fail without a useful message. Each error
// names the file, the line, the key and what was expected, and is a ConfigError (the
// launcher's exit code 2), never yaml-cpp's own "bad conversion".

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/config/config.h"

namespace srics::config {
namespace {

namespace fs = std::filesystem;

class RejectedConfig : public ::testing::Test {
 protected:
  RejectedConfig() {
    dir_ = fs::temp_directory_path() / ("srics-config-rejects-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  ~RejectedConfig() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path) << text;
    return path.string();
  }

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

  fs::path dir_;
};

TEST_F(RejectedConfig, NonScalarKeyNamesFileLineAndWhereItIs) {
  // a list as a key (a flow sequence before the colon) and a mapping as a key
  const std::string list_key = Write("list-key.yaml", "run:\n  name: x\ntransport:\n  [domain_id, run_id]: 5\n");
  EXPECT_EQ(ErrorOf(list_key), list_key + ":4: transport: expected a plain key (a name such as 'domain_id'), "
                                          "got a list as a key");
  const std::string map_key = Write("map-key.yaml", "actors:\n  count: 2\n  ? {a: 1}\n  : 3\n");
  EXPECT_EQ(ErrorOf(map_key), map_key + ":3: actors: expected a plain key (a name such as 'domain_id'), "
                                        "got a mapping as a key");
  // nothing as a key, at the top level
  const std::string null_key = Write("null-key.yaml", "run:\n  name: x\n~: 3\n");
  EXPECT_EQ(ErrorOf(null_key), null_key + ":3: <top>: expected a plain key (a name such as 'domain_id'), "
                                          "got nothing as a key");
  // through extends: the base file is named
  const std::string base = Write("base.yaml", "learner:\n  relabel:\n    [x]: 1\n");
  const std::string top = Write("top.yaml", "extends: base.yaml\nrun:\n  name: y\n");
  EXPECT_EQ(ErrorOf(top), base + ":3: learner.relabel: expected a plain key (a name such as 'domain_id'), "
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
    EXPECT_STREQ(e.what(), "inline.yaml:2: graph: expected a plain key (a name such as 'domain_id'), got a mapping as a key");
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
      {"env:\n  physics:\n    static_objects: glued\n", ":3: env.physics.static_objects: expected one of 'put_back' 'fixed', got 'glued'"},
      {"graph:\n  object_contact_margin_m: -0.01\n", ":2: graph.object_contact_margin_m: expected a number in [0, 1], got '-0.01'"},
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
  EXPECT_NE(ErrorOf(fixed).find("graph.refine_after_publish: needs a learned graph"), std::string::npos) << ErrorOf(fixed);
  const std::string no_share = Write("share.yaml", "graph:\n  refine_after_publish: true\n  refine_share: 0\n");
  EXPECT_NE(ErrorOf(no_share).find("needs refine_share and refine_updates_per_episode above 0"), std::string::npos);
  // windows of 20 steps do not fit training episodes of 10
  const std::string windows = Write("windows.yaml", "graph:\n  refine_after_publish: true\n  window: 20\nactors:\n  train_episode_steps: 10\n");
  EXPECT_NE(ErrorOf(windows).find("graph.window: must not exceed actors.train_episode_steps (10) with refine_after_publish"),
            std::string::npos) << ErrorOf(windows);
  // the same without refinement is fine
  EXPECT_NO_THROW(LoadConfig(windows, {"graph.refine_after_publish=false"}));
}

TEST_F(RejectedConfig, KeepCheckpointsDefaultsToThree) {
  EXPECT_EQ(LoadConfig(Write("empty.yaml", "")).learner.keep_checkpoints, 3);
  EXPECT_EQ(LoadConfig(Write("one.yaml", "learner:\n  keep_checkpoints: 1\n")).learner.keep_checkpoints, 1);
}

}  // namespace
}  // namespace srics::config
