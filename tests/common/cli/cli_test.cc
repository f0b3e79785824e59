// The one argument parser (common/cli): validators name the option and what they expected,
// errors come back as std::invalid_argument, the version is the project's.

#include "common/cli/cli.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace srics::cli {
namespace {

using ::testing::HasSubstr;

// The message of the std::invalid_argument that parsing args throws ("" when none).
std::string ErrorOf(CLI::App& app, const std::vector<std::string>& args) {
  try {
    ParseOrThrow(app, args);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CliTest, VersionIsTheProjectVersion) { EXPECT_STREQ(Version(), SRICS_PROJECT_VERSION); }

TEST(CliTest, ValidatorsNameTheOptionAndWhatTheyExpected) {
  CLI::App app{"", "prog"};
  Configure(app);
  int count = 0;
  double seconds = 1;
  app.add_option("--count", count)->check(Integer(1, 64));
  app.add_option("--seconds", seconds)->check(Number(0));
  EXPECT_EQ(ErrorOf(app, {"--count", "8", "--seconds", "2.5"}), "");
  EXPECT_EQ(count, 8);
  EXPECT_EQ(seconds, 2.5);
  EXPECT_THAT(ErrorOf(app, {"--count", "0"}), HasSubstr("--count: expected an integer from 1 to 64, got '0'"));
  EXPECT_THAT(ErrorOf(app, {"--count", "3x"}), HasSubstr("--count: expected an integer from 1 to 64, got '3x'"));
  EXPECT_THAT(ErrorOf(app, {"--seconds", "-1"}), HasSubstr("--seconds: expected a number >= 0, got '-1'"));
  EXPECT_THAT(ErrorOf(app, {"--seconds", "nan"}), HasSubstr("--seconds"));
  EXPECT_THAT(ErrorOf(app, {"--count"}), HasSubstr("--count"));
  EXPECT_THAT(ErrorOf(app, {"--frobnicate"}), HasSubstr("--frobnicate"));
}

TEST(CliTest, UnboundedIntegersSayNonNegativeOrPositive) {
  CLI::App app{"", "prog"};
  int id = 0, n = 0;
  app.add_option("--id", id)->check(Integer(0, std::numeric_limits<int>::max()));
  app.add_option("--n", n)->check(Integer(1));
  EXPECT_THAT(ErrorOf(app, {"--id", "x1"}), HasSubstr("--id: expected a non-negative integer, got 'x1'"));
  EXPECT_THAT(ErrorOf(app, {"--n", "-2"}), HasSubstr("--n: expected a positive integer, got '-2'"));
}

TEST(CliTest, RepeatedSetOptionsTakeOneValueEach) {
  CLI::App app{"", "prog"};
  std::string config;
  std::vector<std::string> overrides;
  app.add_option("CONFIG", config)->required();
  app.add_option("--set", overrides)->allow_extra_args(false);
  EXPECT_EQ(ErrorOf(app, {"--set", "a=1", "c.yaml", "--set", "b=2"}), "");
  EXPECT_EQ(config, "c.yaml");
  EXPECT_THAT(overrides, ::testing::ElementsAre("a=1", "b=2"));
}

TEST(CliTest, CommandNameIsTheInnermostSubcommandGiven) {
  CLI::App app{"", "srics"};
  CLI::App* run = app.add_subcommand("run");
  std::string config;
  run->add_option("CONFIG", config);
  ParseOrThrow(app, {"run", "c.yaml"});
  EXPECT_EQ(CommandName(app), "srics run");
}

}  // namespace
}  // namespace srics::cli
