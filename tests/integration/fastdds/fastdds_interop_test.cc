// A Fast DDS 2.9 participant (the DDS of ROS 2), built from idl/srics.idl with fastddsgen and
// configured by deploy/fastdds/loopback.xml, reads every topic of a live run of the real role
// processes: the transient-local ones as a late joiner, the others as they are published.

#include <gtest/gtest.h>
#include <signal.h>

#include <cctype>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "deploy/launcher/run_folder.h"
#include "tests/common/files/test_files.h"
#include "tests/integration/system_harness.h"

namespace srics::testing {
namespace {

using files::testing::ReadFile;

// The probe's "topic=NAME key=value ..." lines, by topic.
std::map<std::string, std::map<std::string, std::string>> ParseProbeOutput(const std::string& file) {
  std::map<std::string, std::map<std::string, std::string>> topics;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("topic=", 0) != 0) continue;
    std::istringstream words(line);
    std::map<std::string, std::string> values;
    for (std::string word; words >> word;) {
      const auto eq = word.find('=');
      if (eq != std::string::npos) values[word.substr(0, eq)] = word.substr(eq + 1);
    }
    topics[values["topic"]] = values;
  }
  return topics;
}

uint64_t Number(const std::map<std::string, std::string>& values, const std::string& key) {
  const auto it = values.find(key);
  return it == values.end() ? 0 : std::stoull(it->second);
}

std::string Value(const std::map<std::string, std::string>& values, const std::string& key) {
  const auto it = values.find(key);
  return it == values.end() ? "" : it->second;
}

bool ListHas(const std::map<std::string, std::string>& values, const std::string& key, const std::string& item) {
  const auto it = values.find(key);
  if (it == values.end()) return false;
  std::istringstream in(it->second);
  for (std::string s; std::getline(in, s, ',');)
    if (s == item) return true;
  return false;
}

// Names of module scope (constants, enums, enumerators, structs) that equal a struct field's
// name ignoring case: fastddsgen refuses such an IDL ("already defined"), idlc accepts it.
std::set<std::string> CaseInsensitiveCollisions(std::string idl) {
  const auto lower = [](std::string v) {
    for (char& c : v) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return v;
  };
  idl = std::regex_replace(idl, std::regex("//[^\n]*"), "");
  std::set<std::string> module_names, fields;
  const std::regex constant("const\\s+[\\w ]+?\\s(\\w+)\\s*="), enumeration("enum\\s+(\\w+)\\s*\\{([^}]*)\\}"),
      structure("struct\\s+(\\w+)\\s*\\{([^}]*)\\}"), word("\\w+"), field("(\\w+)\\s*;");
  for (std::sregex_iterator it(idl.begin(), idl.end(), constant), end; it != end; ++it)
    module_names.insert(lower((*it)[1]));
  for (std::sregex_iterator it(idl.begin(), idl.end(), enumeration), end; it != end; ++it) {
    module_names.insert(lower((*it)[1]));
    const std::string body = (*it)[2];
    for (std::sregex_iterator w(body.begin(), body.end(), word); w != end; ++w) module_names.insert(lower((*w)[0]));
  }
  for (std::sregex_iterator it(idl.begin(), idl.end(), structure), end; it != end; ++it) {
    module_names.insert(lower((*it)[1]));
    const std::string body = (*it)[2];
    for (std::sregex_iterator f(body.begin(), body.end(), field); f != end; ++f) fields.insert(lower((*f)[1]));
  }
  std::set<std::string> collisions;
  for (const auto& f : fields)
    if (module_names.count(f)) collisions.insert(f);
  return collisions;
}

TEST(FastDdsInteropTest, IdlNamesDifferFromEveryFieldNameIgnoringCase) {
  // the check finds the collision that once made fastddsgen refuse the file
  EXPECT_EQ(CaseInsensitiveCollisions("module m { const unsigned long CONTRACT_VERSION = 2;\n"
                                      "  @final struct T { unsigned long contract_version; }; };"),
            std::set<std::string>{"contract_version"});
  const auto collisions = CaseInsensitiveCollisions(ReadFile(SourceDir() + "/idl/srics.idl"));
  EXPECT_TRUE(collisions.empty()) << "idl/srics.idl: " << *collisions.begin()
                                  << " is both a module-level name and a field (ignoring case)";
}

// Cyclone's loopback profile lets processes take participant indices up to
// transport.max_participants_per_host; the Fast DDS profile must announce itself to all of them.
TEST(FastDdsInteropTest, FastDdsProfileReachesEveryParticipantIndexOfTheDefaultConfig) {
  const std::string xml = ReadFile(SourceDir() + "/deploy/fastdds/loopback.xml");
  const std::string tag = "<maxInitialPeersRange>";
  const auto at = xml.find(tag);
  ASSERT_NE(at, std::string::npos) << "deploy/fastdds/loopback.xml has no " << tag;
  const int range = std::stoi(xml.substr(at + tag.size()));
  const auto config = config::LoadConfig(SourceDir() + "/deploy/configs/default.yaml");
  EXPECT_GE(range, config.transport.max_participants_per_host + 1)
      << "indices 0.." << config.transport.max_participants_per_host << " need a range of "
      << config.transport.max_participants_per_host + 1;
}

TEST(FastDdsInteropTest, FastDdsSubscriberFromTheIdlReadsEveryTopicOfALiveRunAsALateJoiner) {
  const std::string probe = SRICS_FASTDDS_PROBE;
  if (probe.empty())
    GTEST_SKIP() << "SKIP: fastddsgen or libfastrtps-dev is not installed, so the Fast DDS probe "
                    "was not built (tests/install-test-deps.sh installs them; then re-run cmake)";

  // The graph is given, as `srics run` does it (the graph service publishes it once, so a late
  // joiner can only get it from the writer's history). The probe counts as "historical" the
  // samples written before its reader matched a writer.
  // Node statuses every 10 s: a status written between the probe's match and the delivery of
  // the stored one replaces it (history depth 1); with a status every 2 s a CI run on
  // 2026-12-03 got one historical node status of two.
  System system("fastdds", {"graph.ground_truth=true", "run.total_env_steps=1000000", "actors.eval_every_env_steps=500",
                            "transport.status_period_s=10"});
  launcher::SeedGraphFile(system.config(), system.run_dir());
  system.StartAll(2);
  ASSERT_TRUE(system.WaitUntil(
      [&] {
        return system.graph && system.stats && system.stats->updates > 0 && system.latest_weights > 1 &&
               !system.evals.empty();
      },
      240s))
      << system.Output("learner") << system.Output("actor-0");

  // Stop the actors: the learner runs out of data (its rate limiter) and stops publishing
  // weights, so the weights the probe gets first must come from the learner's history.
  for (const std::string name : {"actor-0", "actor-1"}) system.child(name).Signal(SIGINT);
  ASSERT_TRUE(system.WaitUntil(
      [&] { return system.child("actor-0").Poll().has_value() && system.child("actor-1").Poll().has_value(); }, 30s));
  bool quiet = false;
  for (int attempt = 0; attempt < 30 && !quiet; ++attempt) {
    const size_t published = system.weight_versions.size();
    system.WaitUntil([] { return false; }, 3s);
    quiet = system.weight_versions.size() == published;
  }
  ASSERT_TRUE(quiet) << "the learner kept publishing weights without actors" << system.Output("learner");
  const uint64_t weights_before = system.latest_weights;
  const rl::GraphUpdate graph_before = *system.graph;

  const std::string output = system.run_dir() + "/probe.out";
  launcher::SpawnOptions options;
  options.output_file = output;
  launcher::ChildProcess child =
      launcher::ChildProcess::Spawn({probe, "--profile", SourceDir() + "/deploy/fastdds/loopback.xml", "--domain",
                                     std::to_string(system.config().transport.domain_id), "--run-id",
                                     system.config().transport.run_id, "--timeout-s", "120"},
                                    options);
  // Once it has the transient-local samples, the actors come back: episodes, evaluations and
  // new weights flow again.
  ASSERT_TRUE(
      system.WaitUntil([&] { return ReadFile(output).find("late-joiner:") != std::string::npos || child.Poll(); }, 30s))
      << ReadFile(output);
  ASSERT_TRUE(child.running()) << ReadFile(output);
  system.Start("actor-0");
  system.Start("actor-1");
  std::optional<launcher::ExitStatus> status;
  ASSERT_TRUE(system.WaitUntil([&] { return (status = child.Poll()).has_value(); }, 150s)) << ReadFile(output);
  ASSERT_TRUE(status->success()) << status->Describe() << "\n" << ReadFile(output);

  auto topics = ParseProbeOutput(output);
  for (const char* name :
       {"episode", "policy_weights", "interaction_graph", "eval_result", "learner_stats", "node_status"})
    EXPECT_GT(Number(topics[name], "samples"), 0u) << name << "\n" << ReadFile(output);

  // Late joiner: the latest weights, the graph and node statuses written before it joined.
  const auto& weights = topics["policy_weights"];
  EXPECT_GE(Number(weights, "historical"), 1u) << ReadFile(output);
  EXPECT_EQ(Number(weights, "first_version"), weights_before);
  const auto& graph = topics["interaction_graph"];
  EXPECT_GE(Number(graph, "historical"), 1u) << ReadFile(output);
  EXPECT_EQ(Number(graph, "version"), graph_before.version);
  EXPECT_EQ(Number(graph, "num_entities"), graph_before.graph.num_entities);
  const auto& nodes = topics["node_status"];
  EXPECT_GE(Number(nodes, "historical"), 2u) << "graph-0 and learner-0\n" << ReadFile(output);
  EXPECT_TRUE(ListHas(nodes, "nodes", "graph-0")) << Value(nodes, "nodes");
  EXPECT_TRUE(ListHas(nodes, "nodes", "learner-0")) << Value(nodes, "nodes");

  // Live topics, consistent with what the project's own reader saw.
  const auto& episodes = topics["episode"];
  EXPECT_EQ(Number(episodes, "num_entities"), graph_before.graph.num_entities);
  EXPECT_TRUE(ListHas(episodes, "modes", "train")) << Value(episodes, "modes");
  EXPECT_EQ(Number(topics["eval_result"], "entities"), graph_before.graph.num_entities);
  EXPECT_GE(Number(topics["eval_result"], "max_policy_version"), weights_before);
  EXPECT_GE(Number(topics["learner_stats"], "policy_version"), weights_before);
}

}  // namespace
}  // namespace srics::testing
