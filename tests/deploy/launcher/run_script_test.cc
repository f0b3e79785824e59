// deploy/run.sh's arguments (with SRICS_NO_BUILD=1: the build the suite just made): without a
// CONFIG first, the options go to `srics run` with the default config (the README's
// `./deploy/run.sh --set run.total_env_steps=15000` once stopped with "CONFIG is required");
// a CONFIG first is taken as the config.

#include <gtest/gtest.h>

#include <string>

#include "tests/common/cli/shell_testing.h"

namespace {

struct Output {
  int exit_code = -1;
  std::string text;  // stdout and stderr
};

Output RunScript(const std::string& arguments) {
  const auto [code, text] =
      srics::cli::testing::Shell("SRICS_NO_BUILD=1 SRICS_BUILD_DIR='" + std::string(SRICS_BINARY_DIR) + "' '" +
                                 std::string(SRICS_SOURCE_DIR) + "/deploy/run.sh' " + arguments);
  return {code, text};
}

TEST(RunScriptTest, OptionsFirstGoToSricsRunWithTheDefaultConfig) {
  // a value the default config's validation refuses, named: the default config was read and
  // the option applied to it (nothing is started)
  Output out = RunScript("--set run.total_env_steps=-5");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("total_env_steps"), std::string::npos) << out.text;
  EXPECT_EQ(out.text.find("CONFIG is required"), std::string::npos) << out.text;
  out = RunScript("--help");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("srics run"), std::string::npos) << out.text;
}

TEST(RunScriptTest, AConfigFirstIsTheConfig) {
  const Output out = RunScript("no-such-config.yaml --set run.seed=2");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("no-such-config.yaml"), std::string::npos) << out.text;
}

}  // namespace
