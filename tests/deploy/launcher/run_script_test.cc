// deploy/run.sh's arguments (with SRICS_NO_BUILD=1: the build the suite just made): without a
// CONFIG first, the options go to `srics run` with the default config (the README's
// `./deploy/run.sh --set run.total_env_steps=15000` once stopped with "CONFIG is required");
// a CONFIG first is taken as the config.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace {

struct Output {
  int exit_code = -1;
  std::string text;  // stdout and stderr
};

Output RunScript(const std::string& arguments) {
  const std::string command = "SRICS_NO_BUILD=1 SRICS_BUILD_DIR='" + std::string(SRICS_BINARY_DIR) + "' '" +
                              std::string(SRICS_SOURCE_DIR) + "/deploy/run.sh' " + arguments + " 2>&1";
  Output out;
  FILE* pipe = ::popen(command.c_str(), "r");
  char buffer[4096];
  while (size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.text.append(buffer, n);
  const int status = ::pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
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
