// Validation of received samples and the Cyclone XML of each profile: pure functions, no DDS.

#include "common/transport/validation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/transport/participant.h"
#include "tests/common/transport/test_samples.h"

namespace srics::transport {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// The verdict and that the reason mentions `word`.
void ExpectMalformed(const Validation& v, const std::string& word) {
  EXPECT_EQ(v.verdict, Verdict::kMalformed);
  EXPECT_NE(v.reason.find(word), std::string::npos) << "reason: " << v.reason;
}

TEST(ValidationTest, GoodSamplesOfEveryTypeAreAccepted) {
  const std::string run = "r1";
  const rl::WeightsUpdate w = testing::MakePolicyWeights(1);
  EXPECT_TRUE(Validate(w, {.run_id = run}, ParameterChecksum(w.parameters), run).ok());
  EXPECT_TRUE(Validate(testing::MakeInteractionGraph(1), {.run_id = run}, run).ok());
  EXPECT_TRUE(Validate(testing::MakeEvalResult(1), {.run_id = run}, run).ok());
  EXPECT_TRUE(Validate(testing::MakeLearnerStats(1), {.run_id = run}, run).ok());
  EXPECT_TRUE(Validate(testing::MakeNodeStatus(1), {.run_id = run}, run).ok());
  // an empty expected run id accepts every run (monitors)
  EXPECT_TRUE(Validate(testing::MakeEvalResult(1), {.run_id = "other"}, "").ok());
}

TEST(ValidationTest, OtherRunIsNotMalformed) {
  const Validation v = Validate(testing::MakeEvalResult(1), {.run_id = "run-b"}, "run-a");
  EXPECT_EQ(v.verdict, Verdict::kOtherRun);
  EXPECT_EQ(Validate(testing::MakeNodeStatus(1), {.run_id = "run-b"}, "run-a").verdict, Verdict::kOtherRun);
}

// Episodes carry no struct of their own: their envelope is checked on the received C sample
// (this function), the rest by rl::ValidateEpisode (tests/common/rl/episode_test.cc).
TEST(ValidationTest, EnvelopeOfEverySample) {
  EXPECT_TRUE(ValidateEnvelope(kContractVersion, "r", "r").ok());
  EXPECT_TRUE(ValidateEnvelope(kContractVersion, "r", "").ok());
  ExpectMalformed(ValidateEnvelope(kContractVersion - 1, "r", "r"), "contract_version");
  ExpectMalformed(ValidateEnvelope(kContractVersion + 1, "r", "r"), "contract_version");
  ExpectMalformed(ValidateEnvelope(kContractVersion, "", ""), "run_id");
  EXPECT_TRUE(ValidateEnvelope(kContractVersion, std::string(64, 'x'), "").ok());
  ExpectMalformed(ValidateEnvelope(kContractVersion, std::string(65, 'x'), ""), "run_id");
  EXPECT_EQ(ValidateEnvelope(kContractVersion, "run-b", "run-a").verdict, Verdict::kOtherRun);
}

TEST(ValidationTest, EveryFloatMustBeFinite) {
  rl::WeightsUpdate w = testing::MakePolicyWeights(1);
  w.parameters[10] = kNaN;
  ExpectMalformed(Validate(w, {.run_id = "r"}, ParameterChecksum(w.parameters), "r"), "parameters[10]");

  rl::GraphUpdate g = testing::MakeInteractionGraph(1);
  g.mean_weights[3] = kNaN;
  ExpectMalformed(Validate(g, {.run_id = "r"}, "r"), "mean_weights[3]");
  g = testing::MakeInteractionGraph(1);
  g.threshold = kInf;
  ExpectMalformed(Validate(g, {.run_id = "r"}, "r"), "threshold");

  rl::EvalReport r = testing::MakeEvalResult(1);
  r.summary.entity_distance[2] = kNaN;
  ExpectMalformed(Validate(r, {.run_id = "r"}, "r"), "entity_distance[2]");

  // learner stats are reports: a diverged loss is shown, not dropped
  rl::LearnerReport s = testing::MakeLearnerStats(1);
  s.q_loss = kNaN;
  EXPECT_TRUE(Validate(s, {.run_id = "r"}, "r").ok());
}

TEST(ValidationTest, ContractVersionAndRunIdAreChecked) {
  const rl::EvalReport e = testing::MakeEvalResult(1);
  ExpectMalformed(Validate(e, {kContractVersion + 1, "r"}, "r"), "contract_version");
  ExpectMalformed(Validate(e, {.run_id = ""}, ""), "run_id");
  ExpectMalformed(Validate(testing::MakeNodeStatus(1), {0, "r"}, "r"), "contract_version");
}

TEST(ValidationTest, WeightsChecksumAndVersion) {
  const Envelope of_r{.run_id = "r"};
  rl::WeightsUpdate w = testing::MakePolicyWeights(1);
  const uint32_t sum = ParameterChecksum(w.parameters);
  w.parameters[5] += 1;
  ExpectMalformed(Validate(w, of_r, sum, "r"), "checksum");
  w = testing::MakePolicyWeights(1);
  w.version = 0;
  ExpectMalformed(Validate(w, of_r, sum, "r"), "version");
  w = testing::MakePolicyWeights(1);
  w.parameters.clear();
  ExpectMalformed(Validate(w, of_r, ParameterChecksum(w.parameters), "r"), "parameters");
}

TEST(ValidationTest, ChecksumIsZlibCrc32OfTheBytes) {
  // reference values from Python: zlib.crc32(struct.pack('<3f', 1.0, -2.5, 3.25))
  EXPECT_EQ(ParameterChecksum({}), 0u);
  EXPECT_EQ(ParameterChecksum({1.0f}), 0xACA16A6Au);
  EXPECT_EQ(ParameterChecksum({1.0f, -2.5f, 3.25f}), 0x4E863144u);
  // long enough for the folded (carry-less multiply) path, and not a multiple of its blocks:
  // Python, v = [(i % 1000) * 0.5 - 250 for i in range(100003)], zlib.crc32 of '<100003f'
  std::vector<float> v(100003);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(i % 1000) * 0.5f - 250.0f;
  EXPECT_EQ(ParameterChecksum(v), 0x425187F0u);
}

TEST(ValidationTest, GraphStructureIsChecked) {
  const Envelope of_r{.run_id = "r"};
  const rl::GraphUpdate good = testing::MakeInteractionGraph(1);
  rl::GraphUpdate g = good;
  g.graph.adjacency.pop_back();
  ExpectMalformed(Validate(g, of_r, "r"), "adjacency");
  g = good;
  g.graph.adjacency[0] = 2;
  ExpectMalformed(Validate(g, of_r, "r"), "adjacency[0]");
  g = good;
  g.structure.depth[1] = 6;  // N = 5: a simple path has at most 5 edges
  ExpectMalformed(Validate(g, of_r, "r"), "depths[1]");
  g = good;
  g.structure.depth[1] = 5;
  EXPECT_TRUE(Validate(g, of_r, "r").ok()) << "depth N is a valid longest path";
  g = good;
  g.structure.ancestor_mask[4] = 1ull << 6;
  ExpectMalformed(Validate(g, of_r, "r"), "ancestor_masks[4]");
  g = good;
  g.graph.action_entity = -1;
  ExpectMalformed(Validate(g, of_r, "r"), "action_entity");
}

TEST(ValidationTest, EvalAndStatusRanges) {
  const Envelope of_r{.run_id = "r"};
  rl::EvalReport r = testing::MakeEvalResult(1);
  r.summary.subgoal_success.pop_back();
  ExpectMalformed(Validate(r, of_r, "r"), "subgoal_success");
  r = testing::MakeEvalResult(1);
  r.summary.success_rate = 1.5f;
  ExpectMalformed(Validate(r, of_r, "r"), "success_rate");
  // an attempt cannot undo more solved objects than it began with
  r = testing::MakeEvalResult(1);
  r.summary.independent_solved = 3;
  r.summary.independent_undone = 3;
  EXPECT_TRUE(Validate(r, of_r, "r").ok());
  r.summary.independent_undone = 4;
  ExpectMalformed(Validate(r, of_r, "r"), "independent_undone (4) exceeds independent_solved (3)");
  rl::NodeStatus n = testing::MakeNodeStatus(1);
  n.report.phase = static_cast<rl::NodePhase>(9);
  ExpectMalformed(Validate(n, of_r, "r"), "state");
  n = testing::MakeNodeStatus(1);
  n.role.clear();
  ExpectMalformed(Validate(n, of_r, "r"), "role");
}

// Issue 15: each rejection names the counter it counts in ("<topic>.<check>").
TEST(ValidationTest, EveryRejectionNamesItsCounter) {
  rl::WeightsUpdate w = testing::MakePolicyWeights(1);
  const uint32_t sum = ParameterChecksum(w.parameters);
  EXPECT_EQ(Validate(w, {0, "r"}, sum, "r").counter, "weights.envelope");
  w.parameters[5] += 1;
  EXPECT_EQ(Validate(w, {.run_id = "r"}, sum, "r").counter, "weights.checksum");
  w = testing::MakePolicyWeights(1);
  w.parameters[7] = kNaN;
  EXPECT_EQ(Validate(w, {.run_id = "r"}, ParameterChecksum(w.parameters), "r").counter, "weights.nonfinite");
  rl::GraphUpdate g = testing::MakeInteractionGraph(1);
  g.structure.depth.pop_back();
  EXPECT_EQ(Validate(g, {.run_id = "r"}, "r").counter, "graph.size");
  g = testing::MakeInteractionGraph(1);
  g.graph.adjacency[2] = 7;
  EXPECT_EQ(Validate(g, {.run_id = "r"}, "r").counter, "graph.range");
  rl::EvalReport e = testing::MakeEvalResult(1);
  e.summary.avg_distance = kInf;
  EXPECT_EQ(Validate(e, {.run_id = "r"}, "r").counter, "eval.nonfinite");
  rl::NodeStatus n = testing::MakeNodeStatus(1);
  n.host = std::string(200, 'h');
  EXPECT_EQ(Validate(n, {.run_id = "r"}, "r").counter, "status.size");
  EXPECT_EQ(ValidateEnvelope(kContractVersion, "", "r").counter, "episode.envelope");
  EXPECT_TRUE(Validate(testing::MakeNodeStatus(1), {.run_id = "r"}, "r").counter.empty());
}

// Finite but huge parameters overflowed the actors' policies into NaN actions: refused.
TEST(ValidationTest, WeightsBeyondTheParameterBoundAreRefused) {
  const Envelope of_r{.run_id = "r"};
  rl::WeightsUpdate w = testing::MakePolicyWeights(1);
  EXPECT_TRUE(Validate(w, of_r, ParameterChecksum(w.parameters), "r").ok()) << "+-kMaxAbsParameter itself is allowed";
  w.parameters[9] = 1e30f;
  const Validation v = Validate(w, of_r, ParameterChecksum(w.parameters), "r");
  ExpectMalformed(v, "parameters[9]");
  EXPECT_EQ(v.counter, "weights.magnitude");
  w.parameters[9] = -std::nextafter(rl::kMaxAbsParameter, 2 * rl::kMaxAbsParameter);
  EXPECT_EQ(Validate(w, of_r, ParameterChecksum(w.parameters), "r").counter, "weights.magnitude");
}

TEST(ValidationTest, EvaluationDistancesAreNotNegative) {
  rl::EvalReport e = testing::MakeEvalResult(1);
  e.summary.entity_distance[1] = -0.5f;
  ExpectMalformed(Validate(e, {.run_id = "r"}, "r"), "entity_distance[1]");
  e = testing::MakeEvalResult(1);
  e.summary.avg_object_distance = -1;
  EXPECT_EQ(Validate(e, {.run_id = "r"}, "r").counter, "eval.range");
}

TEST(RejectionCountersTest, CountedPerReasonSummedAndSummarized) {
  CounterTable table;
  table.CountRejection("weights.checksum");
  table.CountRejection("graph.entities");
  table.CountRejection("weights.checksum");
  const auto all = table.Rejections();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all.at("weights.checksum"), 2u);
  EXPECT_EQ(all.at("graph.entities"), 1u);
  EXPECT_EQ(RejectionSummary(all), "graph.entities=1 weights.checksum=2");
  EXPECT_EQ(RejectionSummary({}), "");
}

// ------------------------------------------------------------------------------ Cyclone XML

// Expects every one of `present` in the XML and none of `absent`.
void ExpectXml(const std::string& xml, std::initializer_list<std::string> present,
               std::initializer_list<std::string> absent) {
  for (const std::string& part : present) EXPECT_NE(xml.find(part), std::string::npos) << part;
  for (const std::string& part : absent) EXPECT_EQ(xml.find(part), std::string::npos) << part;
}

TEST(CycloneConfigTest, LoopbackRaisesParticipantIndexAndDisablesMulticast) {
  config::TransportConfig c;
  c.max_participants_per_host = 99;
  const std::string xml = CycloneConfigFor(c);
  // knobs not in the config stay for Cyclone to expand (environment or default)
  ExpectXml(xml,
            {"<MaxAutoParticipantIndex>99</MaxAutoParticipantIndex>", "<AllowMulticast>false</AllowMulticast>",
             "<MaxMessageSize>65500B</MaxMessageSize>", "<Peer address=\"127.0.0.1\"/>", "${SRICS_DDS_WHC_HIGH:-8MB}"},
            {"${SRICS_DDS_MAX_PARTICIPANTS"});
}

TEST(CycloneConfigTest, UnicastListsEveryPeerAndTheInterface) {
  config::TransportConfig c;
  c.profile = config::CycloneProfile::kUnicast;
  c.peers = "10.0.0.1, 10.0.0.2,host-c";
  c.network_interface = "eth1";
  ExpectXml(CycloneConfigFor(c),
            {"<Peer address=\"10.0.0.1\"/>", "<Peer address=\"10.0.0.2\"/>", "<Peer address=\"host-c\"/>",
             "name=\"eth1\" autodetermine=\"false\""},
            {"<Peer address=\"${SRICS_DDS_PEER"});
  c.peers = "a\"/><Evil";
  EXPECT_THROW(CycloneConfigFor(c), std::invalid_argument);
}

TEST(CycloneConfigTest, LanLetsCycloneChooseWithoutInterface) {
  config::TransportConfig c;
  c.profile = config::CycloneProfile::kLan;
  const std::string xml = CycloneConfigFor(c);
  EXPECT_NE(xml.find("<AllowMulticast>true</AllowMulticast>"), std::string::npos);
  EXPECT_NE(xml.find("name=\"\" autodetermine=\"true\""), std::string::npos);
}

TEST(CycloneConfigTest, FileEnvironmentAndPortRange) {
  config::TransportConfig c;
  c.profile = config::CycloneProfile::kEnvironment;
  EXPECT_EQ(CycloneConfigFor(c), "");
  c.profile = config::CycloneProfile::kFile;
  c.cyclone_xml = std::string(SRICS_SOURCE_DIR) + "/deploy/cyclonedds/loopback.xml";
  EXPECT_EQ(CycloneConfigFor(c), "file://" + c.cyclone_xml);
  c.cyclone_xml = "/nonexistent/cyclone.xml";
  EXPECT_THROW(CycloneConfigFor(c), std::invalid_argument);
  c.profile = config::CycloneProfile::kLoopback;
  c.domain_id = 232;  // 7400 + 250 * 232 + 11 + 2 * 64 > 65535
  EXPECT_THROW(CycloneConfigFor(c), std::invalid_argument);
  c.domain_id = 230;
  EXPECT_NO_THROW(CycloneConfigFor(c));
}

}  // namespace
}  // namespace srics::transport
