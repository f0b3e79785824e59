// The config library: typed parsing, defaults, and errors that name file, line, key and
// what was expected; `extends:` merging and "a.b=value" overrides.

#include "common/config/config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/common/config/config_files.h"

namespace srics::config {
namespace {

using testing::ConfigFiles;

// The ConfigError message of `load`, or "" when it did not throw.
template <typename F>
std::string ErrorOf(F load) {
  try {
    load();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST_F(ConfigFiles, EmptyFileGivesTheDefaults) {
  const Config c = LoadConfig(Write("empty.yaml", ""));
  EXPECT_EQ(c.transport.domain_id, TransportConfig{}.domain_id);
  EXPECT_EQ(c.transport.profile, CycloneProfile::kLoopback);
  EXPECT_EQ(c.run.seed, RunConfig{}.seed);
  EXPECT_EQ(c.run.method, Method::kSrics);
}

TEST_F(ConfigFiles, ValuesAreParsedIntoTypedFields) {
  const std::string file = Write("run.yaml",
                                 "run:\n"
                                 "  name: exp\n"
                                 "  seed: 12345678901\n"
                                 "  method: smorl\n"
                                 "  log_to_file: false\n"
                                 "transport:\n"
                                 "  domain_id: 7\n"
                                 "  run_id: abc\n"
                                 "  profile: unicast\n"
                                 "  peers: 10.0.0.1,10.0.0.2\n"
                                 "  liveliness_lease_s: 1.5\n"
                                 "  episode_batch_ms: 0\n");
  const Config c = LoadConfig(file);
  EXPECT_EQ(c.run.name, "exp");
  EXPECT_EQ(c.run.seed, 12345678901ull);
  EXPECT_EQ(c.run.method, Method::kSmorl);
  EXPECT_FALSE(c.run.log_to_file);
  EXPECT_EQ(c.transport.domain_id, 7);
  EXPECT_EQ(c.transport.run_id, "abc");
  EXPECT_EQ(c.transport.profile, CycloneProfile::kUnicast);
  EXPECT_EQ(c.transport.peers, "10.0.0.1,10.0.0.2");
  EXPECT_DOUBLE_EQ(c.transport.liveliness_lease_s, 1.5);
  EXPECT_EQ(c.transport.episode_batch_ms, 0);  // the default is 2
  EXPECT_EQ(TransportConfig{}.episode_batch_ms, 2);
  EXPECT_EQ(c.source_file, file);
  EXPECT_NE(c.effective_yaml.find("domain_id: 7"), std::string::npos);
}

// A run folder keeps every setting as its binary resolved it (resolved-config.yaml): the
// defaults too, so a default that changes between binaries shows as a change.
TEST_F(ConfigFiles, ResolvedYamlHoldsEveryDefaultAndEveryGivenValue) {
  const Config c = LoadConfig(Write("resolved.yaml",
                                    "transport:\n  domain_id: 7\n"
                                    "env:\n  objects:\n    - {static: true}\n    - {}\n"));
  EXPECT_NE(c.resolved_yaml.find("domain_id: 7"), std::string::npos) << c.resolved_yaml;
  EXPECT_NE(c.resolved_yaml.find("selectivity_form: paper"), std::string::npos) << c.resolved_yaml;
  EXPECT_EQ(c.effective_yaml.find("selectivity_form"), std::string::npos) << c.effective_yaml;
  EXPECT_NE(c.resolved_yaml.find("batch_size: 2048"), std::string::npos) << c.resolved_yaml;  // agent.sac default
  EXPECT_NE(c.resolved_yaml.find("static: true"), std::string::npos) << c.resolved_yaml;      // lists of mappings
  // num_pucks follows the objects list: not recorded at its default of 3 beside a list of 2
  EXPECT_EQ(c.resolved_yaml.find("num_pucks"), std::string::npos) << c.resolved_yaml;
  EXPECT_EQ(c.env.num_pucks, 2);
  // the same settings spelled otherwise (a key given its default value) resolve the same
  const Config spelled = LoadConfig(Write("spelled.yaml",
                                          "transport:\n  domain_id: 7\n"
                                          "agent:\n  reward:\n    selectivity_form: paper\n"
                                          "env:\n  objects:\n    - {static: true}\n    - {}\n"));
  EXPECT_NE(spelled.effective_yaml, c.effective_yaml);
  EXPECT_EQ(spelled.resolved_yaml, c.resolved_yaml);
}

// ------------------------------------------------------------------ the three error kinds

TEST_F(ConfigFiles, TypoedKeyNamesFileLineKeyAndSuggestion) {
  const std::string file = Write("typo.yaml",
                                 "transport:\n"
                                 "  domain_id: 3\n"
                                 "  domian_id: 4\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  EXPECT_NE(message.find(file + ":3"), std::string::npos) << message;
  EXPECT_NE(message.find("transport.domian_id"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown key"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'domain_id'"), std::string::npos) << message;
}

TEST_F(ConfigFiles, TypoedSectionIsAnErrorToo) {
  const std::string file = Write("typo.yaml", "trasport:\n  domain_id: 3\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  // the line of the value: a mapping starts at its first key
  EXPECT_NE(message.find(file + ":2"), std::string::npos) << message;
  EXPECT_NE(message.find("trasport: unknown key (did you mean 'transport'?)"), std::string::npos) << message;
}

TEST_F(ConfigFiles, FarFetchedKeyGetsNoSuggestion) {
  const std::string message = ErrorOf([&] { LoadConfig(Write("far.yaml", "transport:\n  completely_else: 1\n")); });
  EXPECT_NE(message.find("transport.completely_else: unknown key"), std::string::npos) << message;
  EXPECT_EQ(message.find("did you mean"), std::string::npos) << message;
}

TEST_F(ConfigFiles, WrongTypeNamesFileLineKeyExpectationAndValue) {
  const std::string file = Write("type.yaml",
                                 "run:\n"
                                 "  name: x\n"
                                 "transport:\n"
                                 "  domain_id: seven\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  EXPECT_EQ(message, file + ":4: transport.domain_id: expected an integer in [0, 232], got 'seven'");
}

TEST_F(ConfigFiles, OutOfRangeNamesFileLineKeyAndRange) {
  const std::string file = Write("range.yaml", "transport:\n  liveliness_lease_s: 0.001\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  EXPECT_EQ(message, file + ":2: transport.liveliness_lease_s: expected a number in [0.05, 3600], got '0.001'");
}

TEST_F(ConfigFiles, OtherTypeErrors) {
  const struct {
    const char* yaml;
    const char* message;
  } cases[] = {
      {"transport:\n  profile: wifi\n",
       "transport.profile: expected one of 'loopback' 'lan' 'unicast' 'file' 'environment', got "
       "'wifi'"},
      {"run:\n  log_to_file: maybe\n", "run.log_to_file: expected true or false, got 'maybe'"},
      {"run:\n  seed: -3\n", "run.seed: expected a non-negative integer, got '-3'"},
      {"transport: [1, 2]\n", "transport: expected a mapping, got a list"},
      {"run:\n  name: [a]\n", "run.name: expected a non-empty string, got a list"},
      {"transport:\n  domain_id: 1.5\n", "got '1.5'"},
  };
  for (const auto& c : cases) {
    const std::string message = ErrorOf([&] { LoadConfig(Write("case.yaml", c.yaml)); });
    EXPECT_NE(message.find(c.message), std::string::npos) << message;
  }
}

TEST_F(ConfigFiles, CrossFieldRulesNameTheKey) {
  const std::string file = Write("rule.yaml", "transport:\n  profile: unicast\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find("transport.peers: profile 'unicast' needs peers"), std::string::npos) << message;
}

TEST_F(ConfigFiles, InvalidYamlAndMissingFile) {
  const std::string file = Write("bad.yaml", "transport:\n  domain_id: [1\n");
  const std::string message = ErrorOf([&] { LoadConfig(file); });
  EXPECT_NE(message.find(file + ":"), std::string::npos) << message;
  EXPECT_NE(message.find("not valid YAML"), std::string::npos) << message;
  EXPECT_NE(ErrorOf([&] { LoadConfig((dir_ / "nope.yaml").string()); }).find("no such config file"), std::string::npos);
}

// ------------------------------------------------------------------------------- extends

TEST_F(ConfigFiles, ExtendsMergesKeyByKeyAndTheExtendingFileWins) {
  Write("base/base.yaml",
        "run:\n"
        "  name: base\n"
        "  seed: 5\n"
        "transport:\n"
        "  domain_id: 10\n"
        "  run_id: base-run\n");
  const std::string top = Write("top.yaml",
                                "extends: base/base.yaml\n"
                                "transport:\n"
                                "  domain_id: 11\n");
  const Config c = LoadConfig(top);
  EXPECT_EQ(c.transport.domain_id, 11);       // overridden
  EXPECT_EQ(c.transport.run_id, "base-run");  // kept from the base (same mapping)
  EXPECT_EQ(c.run.name, "base");              // kept from the base (other mapping)
  EXPECT_EQ(c.run.seed, 5u);
}

TEST_F(ConfigFiles, ExtendsChainsAndErrorsNameTheFileTheKeyCameFrom) {
  const std::string base = Write("base.yaml",
                                 "run:\n"
                                 "  name: base\n"
                                 "transport:\n"
                                 "  max_participants_per_host: 5000\n");
  Write("middle.yaml", "extends: base.yaml\nrun:\n  seed: 9\n");
  const std::string top = Write("top.yaml", "extends: middle.yaml\ntransport:\n  domain_id: 3\n");
  const std::string message = ErrorOf([&] { LoadConfig(top); });
  // the bad value lives on line 4 of base.yaml, not in top.yaml
  EXPECT_EQ(message, base +
                         ":4: transport.max_participants_per_host: expected an integer in "
                         "[1, 1000], got '5000'");
}

TEST_F(ConfigFiles, UnknownKeyInBaseFileNamesTheBase) {
  const std::string base = Write("base.yaml", "transport:\n  domain: 3\n");
  const std::string top = Write("top.yaml", "extends: base.yaml\ntransport:\n  domain_id: 4\n");
  const std::string message = ErrorOf([&] { LoadConfig(top); });
  EXPECT_NE(message.find(base + ":2: transport.domain: unknown key"), std::string::npos) << message;
}

TEST_F(ConfigFiles, ExtendsCycleAndBadExtends) {
  Write("a.yaml", "extends: b.yaml\n");
  const std::string b = Write("b.yaml", "extends: a.yaml\n");
  EXPECT_NE(ErrorOf([&] { LoadConfig(b); }).find("deeper than 8"), std::string::npos);
  const std::string bad = Write("c.yaml", "extends: {a: 1}\n");
  EXPECT_NE(ErrorOf([&] { LoadConfig(bad); }).find("extends: expected a file name"), std::string::npos);
  const std::string missing = Write("d.yaml", "extends: missing.yaml\n");
  EXPECT_NE(ErrorOf([&] { LoadConfig(missing); }).find("missing.yaml: no such config file"), std::string::npos);
}

TEST_F(ConfigFiles, ExtendsListMergesInOrderLaterWins) {
  Write("a.yaml", "transport:\n  domain_id: 1\n  run_id: from-a\n");
  Write("b.yaml", "transport:\n  domain_id: 2\n");
  const std::string top = Write("top.yaml", "extends: [a.yaml, b.yaml]\nrun:\n  seed: 3\n");
  const Config c = LoadConfig(top);
  EXPECT_EQ(c.transport.domain_id, 2);
  EXPECT_EQ(c.transport.run_id, "from-a");
  EXPECT_EQ(c.run.seed, 3u);
}

// ----------------------------------------------------------------------------- overrides

TEST_F(ConfigFiles, OverridesApplyOnTopOfFiles) {
  const std::string file = Write("run.yaml", "transport:\n  domain_id: 3\n  run_id: a\n");
  const Config c = LoadConfig(file, {"transport.domain_id=9", "run.seed=77", "run.method=sac_her"});
  EXPECT_EQ(c.transport.domain_id, 9);
  EXPECT_EQ(c.transport.run_id, "a");  // a sibling of an overridden key survives
  EXPECT_EQ(c.run.seed, 77u);
  EXPECT_EQ(c.run.method, Method::kSacHer);
}

TEST_F(ConfigFiles, OverrideErrorsNameTheCommandLine) {
  const std::string file = Write("run.yaml", "transport:\n  domain_id: 3\n");
  const std::string message = ErrorOf([&] { LoadConfig(file, {"transport.domain_id=500"}); });
  EXPECT_EQ(message, "command line: transport.domain_id: expected an integer in [0, 232], got '500'");
  const std::string typo = ErrorOf([&] { LoadConfig(file, {"transport.domainid=5"}); });
  EXPECT_NE(typo.find("command line: transport.domainid: unknown key (did you mean 'domain_id'?)"), std::string::npos)
      << typo;
  EXPECT_NE(ErrorOf([&] { LoadConfig(file, {"no-equals-sign"}); }).find("expected key.path=value"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { LoadConfig(file, {"transport..domain_id=1"}); }).find("empty key"), std::string::npos);
}

TEST_F(ConfigFiles, OverrideReplacesAWholeMappingWithAScalarOnlyWhenAsked) {
  const std::string file = Write("run.yaml", "transport:\n  domain_id: 3\n");
  const std::string message = ErrorOf([&] { LoadConfig(file, {"transport=5"}); });
  EXPECT_NE(message.find("transport: expected a mapping"), std::string::npos) << message;
}

// Every method name the parser accepts runs its own pipeline; any other name is an error
// naming run.method (the launcher exits 2 on it: tests/deploy/launcher/launcher_test.cc).
TEST_F(ConfigFiles, MethodsAreTheImplementedOnesAndAnyOtherNameIsAnError) {
  const std::string file = Write("run.yaml", "run:\n  seed: 3\n");
  EXPECT_EQ(LoadConfig(file, {"run.method=hac"}).run.method, Method::kHac);
  for (const char* method : {"feudal", "HAC", "sac", ""}) {
    const std::string message = ErrorOf([&] { LoadConfig(file, {std::string("run.method=") + method}); });
    EXPECT_NE(message.find("run.method: expected one of 'srics' 'srics_no_selectivity' "
                           "'srics_no_selectivity_no_order' 'smorl' 'sac_her' 'hac'"),
              std::string::npos)
        << method << ": " << message;
  }
}

TEST_F(ConfigFiles, HacSettingsHaveDefaultsAndRanges) {
  const Config defaults = LoadConfig(Write("empty.yaml", ""));
  EXPECT_EQ(defaults.agent.hac.horizon, 20);
  EXPECT_DOUBLE_EQ(defaults.agent.hac.subgoal_test_probability, 0.3);
  EXPECT_DOUBLE_EQ(defaults.agent.hac.goal_threshold, 0.05);
  EXPECT_EQ(defaults.agent.hac.hindsight_goals, 3);
  const std::string file = Write("hac.yaml", "agent:\n  hac:\n    horizon: 10\n    hindsight_goals: 0\n");
  EXPECT_EQ(LoadConfig(file).agent.hac.horizon, 10);
  EXPECT_NE(ErrorOf([&] {
              LoadConfig(file, {"agent.hac.horizon=101"});
            }).find("agent.hac.horizon: expected an integer in [1, 100], got '101'"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              LoadConfig(file, {"agent.hac.subgoal_test_probability=1.5"});
            }).find("agent.hac.subgoal_test_probability"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { LoadConfig(file, {"agent.hac.goal_threshold=0"}); }).find("agent.hac.goal_threshold"),
            std::string::npos);
}

TEST_F(ConfigFiles, LearnerThreadsDefaultToOneAndAreChecked) {
  const std::string file = Write("threads.yaml", "");
  EXPECT_EQ(LoadConfig(file).learner.threads, 1);
  EXPECT_EQ(LoadConfig(file, {"learner.threads=2"}).learner.threads, 2);
  EXPECT_NE(ErrorOf([&] {
              LoadConfig(file, {"learner.threads=0"});
            }).find("learner.threads: expected an integer in [1, 64], got '0'"),
            std::string::npos);
}

TEST_F(ConfigFiles, LearnerPrecisionDefaultsToFp32AndNamesItsChoices) {
  const std::string file = Write("precision.yaml", "");
  EXPECT_EQ(LoadConfig(file).learner.precision, ProductPrecision::kFp32);
  // not recorded unless given: older run folders resolve as they did and resume
  EXPECT_EQ(LoadConfig(file).resolved_yaml.find("precision"), std::string::npos);
  EXPECT_NE(LoadConfig(file, {"learner.precision=bf16"}).resolved_yaml.find("precision: bf16"), std::string::npos);
  EXPECT_EQ(LoadConfig(file, {"learner.precision=bf16"}).learner.precision, ProductPrecision::kBf16);
  const std::string error = ErrorOf([&] { LoadConfig(file, {"learner.precision=fp16"}); });
  EXPECT_NE(error.find("learner.precision"), std::string::npos) << error;
  EXPECT_NE(error.find("fp16"), std::string::npos) << error;
}

TEST_F(ConfigFiles, InProcessThreadsDefaultsToOneAndIsRecordedOnlyWhenGiven) {
  const std::string file = Write("in_process_threads.yaml", "");
  EXPECT_EQ(LoadConfig(file).run.in_process_threads, 1);
  // not recorded unless given: older run folders resolve as they did and resume
  EXPECT_EQ(LoadConfig(file).resolved_yaml.find("in_process_threads"), std::string::npos);
  const Config two = LoadConfig(file, {"run.in_process_threads=2"});
  EXPECT_EQ(two.run.in_process_threads, 2);
  EXPECT_NE(two.resolved_yaml.find("in_process_threads: 2"), std::string::npos) << two.resolved_yaml;
  EXPECT_NE(ErrorOf([&] {
              LoadConfig(file, {"run.in_process_threads=3"});
            }).find("run.in_process_threads: expected an integer in [1, 2], got '3'"),
            std::string::npos);
}

// ------------------------------------------------------------------------- ParseConfig

TEST(ParseConfigTest, TextUsesTheGivenNameInErrors) {
  const std::string message = [] {
    try {
      ParseConfig("transport:\n  domain_id: -1\n", "received.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_EQ(message, "received.yaml:2: transport.domain_id: expected an integer in [0, 232], got '-1'");
  EXPECT_EQ(ParseConfig("transport:\n  domain_id: 4\n", "x").transport.domain_id, 4);
}

}  // namespace
}  // namespace srics::config
