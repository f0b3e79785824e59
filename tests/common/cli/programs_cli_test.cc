// Every program of the project on one argument parser: --help and --version answer with exit
// code 0, a bad argument exits with 2 and the message names it. One parametrized test over
// the programs and srics's subcommands.

#include <cctype>
#include <ostream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/common/cli/shell_testing.h"

namespace {

using ::testing::HasSubstr;

struct Program {
  std::string name;                  // as in messages and --version: "srics run", "srics-actor"
  std::vector<std::string> command;  // the executable and, for srics, the subcommand
  std::vector<std::string> bad;      // arguments with one bad value
  std::string named;                 // what the error must name
};

const std::string kConfig = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml";

std::vector<Program> Programs() {
  return {
      {"srics", {SRICS_PROGRAM}, {"frobnicate"}, "frobnicate"},
      {"srics run", {SRICS_PROGRAM, "run"}, {kConfig, "--actors", "zero"}, "--actors"},
      {"srics sweep", {SRICS_PROGRAM, "sweep"}, {kConfig, "--methods", "srics", "--seeds", "1-x"}, "--seeds"},
      {"srics compare", {SRICS_PROGRAM, "compare"}, {"/tmp", "--out"}, "--out"},
      {"srics eval", {SRICS_PROGRAM, "eval"}, {"/tmp", "--episodes", "0"}, "--episodes"},
      {"srics learn-graph", {SRICS_PROGRAM, "learn-graph"}, {"--random-table", "-3"}, "--random-table"},
      {"srics column", {SRICS_PROGRAM, "column"}, {"/tmp/x.csv"}, "COLUMN"},
      {"srics-actor", {SRICS_ACTOR_PROGRAM}, {kConfig, "--id", "x1"}, "--id"},
      {"srics-learner", {SRICS_LEARNER_PROGRAM}, {kConfig, "--log-level"}, "--log-level"},
      {"srics-graph", {SRICS_GRAPH_PROGRAM}, {kConfig, "--run-dir"}, "--run-dir"},
      {"srics-monitor", {SRICS_MONITOR_PROGRAM}, {kConfig, "--for", "-1"}, "--for"},
      {"srics-draw-episode", {SRICS_DRAW_EPISODE_PROGRAM}, {"--steps", "many"}, "--steps"},
  };
}

// Runs the command with extra arguments: the exit code and stdout + stderr.
std::pair<int, std::string> RunProgram(std::vector<std::string> argv, const std::vector<std::string>& extra) {
  argv.insert(argv.end(), extra.begin(), extra.end());
  std::string line;
  for (const std::string& a : argv) line += "'" + a + "' ";
  return srics::cli::testing::Shell(line);
}

void PrintTo(const Program& p, std::ostream* out) { *out << p.name; }

class ProgramsCliTest : public ::testing::TestWithParam<Program> {};

TEST_P(ProgramsCliTest, HelpVersionAndBadArguments) {
  const Program& p = GetParam();
  {
    const auto [code, output] = RunProgram(p.command, {"--help"});
    EXPECT_EQ(code, 0) << output;
    EXPECT_THAT(output, HasSubstr("Usage: " + p.name)) << output;
    EXPECT_THAT(output, HasSubstr("--version")) << output;
  }
  {
    const auto [code, output] = RunProgram(p.command, {"--version"});
    EXPECT_EQ(code, 0) << output;
    EXPECT_EQ(output, p.name + " " + SRICS_PROJECT_VERSION + "\n");
  }
  {
    const auto [code, output] = RunProgram(p.command, p.bad);
    EXPECT_EQ(code, 2) << output;
    EXPECT_THAT(output, HasSubstr(p.name + ": ")) << output;
    EXPECT_THAT(output, HasSubstr(p.named)) << output;
  }
  {
    // an unknown option, given after otherwise good arguments
    std::vector<std::string> args = {"--frobnicate"};
    if (p.name != "srics" && p.bad.front()[0] != '-') args.insert(args.begin(), p.bad.front());
    const auto [code, output] = RunProgram(p.command, args);
    EXPECT_EQ(code, 2) << output;
    EXPECT_THAT(output, HasSubstr("--frobnicate")) << output;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryProgram, ProgramsCliTest, ::testing::ValuesIn(Programs()),
                         [](const ::testing::TestParamInfo<Program>& info) {
                           std::string name;
                           for (char c : info.param.name) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
