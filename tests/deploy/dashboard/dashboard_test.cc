// The dashboard's JSON document: from a MonitorState built by hand, and from a run folder's
// files, with every figure checked against the CSV rows it came from; the episode media it
// may serve; the HTTP server's routes, a taken port and paths outside the media.

#include "deploy/dashboard/dashboard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/config/config.h"
#include "common/graph_file/graph_file.h"
#include "deploy/dashboard/json_writer.h"
#include "deploy/dashboard/run_folder_source.h"
#include "deploy/monitor/csv_sink.h"
#include "tests/deploy/dashboard/json_reader.h"
#include "tests/deploy/monitor/test_states.h"

namespace srics::dashboard {
namespace {

namespace fs = std::filesystem;
namespace mon = srics::monitor;
using mon::testing::Eval;
using mon::testing::Graph;

using Node = testing::Json;
// The document read back strictly (any text that is not exactly JSON fails the test).
Node Parse(const std::string& json) { return Node::Parse(json); }

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> out(1);
  for (char c : text) {
    if (c == separator)
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

// A CSV file as rows of column -> value (no quoted commas in the files the tests write).
std::vector<std::map<std::string, std::string>> ReadCsv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = Split(line, ',');
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = Split(line, ',');
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

double Number(const std::string& text) { return std::stod(text); }

TEST(JsonWriterTest, NestsEscapesAndWritesNonFiniteAsNull) {
  JsonWriter json;
  json.BeginObject();
  json.Key("text").String("a \"quoted\"\\ line\nand\x01 more");
  json.Key("list").BeginArray().Number(0.5).Number(NAN).Number(INFINITY).Unsigned(18446744073709551615ull).EndArray();
  json.Key("empty").BeginObject().EndObject();
  json.Key("flags").BeginArray().Bool(true).Null().Integer(-3).EndArray();
  json.EndObject();
  EXPECT_EQ(json.Take(),
            "{\"text\":\"a \\\"quoted\\\"\\\\ line\\nand\\u0001 more\",\"list\":[0.5,null,null,18446744073709551615],"
            "\"empty\":{},\"flags\":[true,null,-3]}");
}

TEST(DashboardJsonTest, RunsNodesGraphAndLearnerFromTheMonitorState) {
  const auto now = mon::Clock::now();
  mon::MonitorState state;
  state.lost_after = std::chrono::seconds(5);
  mon::Apply(&state, "r1", Eval(0, 0, 0.25f), now);  // the passive policy
  mon::Apply(&state, "r1", Eval(5, 1000, 0.2f), now);
  mon::Apply(&state, "r1", Eval(9, 2000, 0.125f), now);
  mon::Apply(&state, "r1", Graph(), now);
  rl::LearnerReport stats;
  stats.updates = 300;
  stats.q_loss = 0.5f;
  stats.budget_env_steps = 4000;
  mon::testing::SetTrainingSteps(&stats, 2100);
  mon::Apply(&state, "r1", stats, now);
  mon::Apply(&state, "r1", mon::testing::Node("learner", 0, rl::NodePhase::kTraining), now);
  mon::Apply(&state, "r1", mon::testing::Node("actor", 1, rl::NodePhase::kStopping), now - std::chrono::seconds(60));
  mon::Apply(&state, "r1", mon::testing::Node("actor", 2, rl::NodePhase::kTraining), now - std::chrono::seconds(60));
  mon::RenderOptions render;
  render.title = "t";
  render.processes.push_back({.name = "actor-1", .pid = 42, .state = "running", .restarts = 2});
  render.events = {"[00:00:01] started"};

  const Node doc = Parse(DashboardJson(state, now, render, {.source = "dds", .poll_ms = 1500}));
  EXPECT_EQ(doc["schema"].as<std::string>(), "srics-dashboard/1");
  EXPECT_EQ(doc["poll_ms"].as<int>(), 1500);
  ASSERT_EQ(doc["runs"].size(), 1u);
  const Node run = doc["runs"][0];
  EXPECT_EQ(run["run_id"].as<std::string>(), "r1");
  EXPECT_EQ(run["env_steps"].as<uint64_t>(), 2100u);  // the learner's count beats the last eval's
  EXPECT_EQ(run["budget_env_steps"].as<uint64_t>(), 4000u);
  EXPECT_TRUE(run["env_steps_per_second"].IsNull());  // one stats sample: no rate yet
  EXPECT_EQ(run["passive"]["avg_object_distance"].as<double>(), 0.25);
  ASSERT_EQ(run["evals"].size(), 2u);
  EXPECT_EQ(run["evals"][1]["env_steps"].as<uint64_t>(), 2000u);
  EXPECT_EQ(run["evals"][1]["avg_object_distance"].as<double>(), 0.125);
  EXPECT_EQ(run["latest_eval"]["policy_version"].as<uint64_t>(), 9u);
  EXPECT_EQ(run["evals"][1]["subgoal_success"][2].as<double>(), 0.25);
  EXPECT_EQ(run["learner"]["updates"].as<uint64_t>(), 300u);
  EXPECT_EQ(run["learner_history"]["q_loss"][0].as<double>(), 0.5);
  // the graph: rows of the matrix, the kept edges only (not the diagonal)
  const Node graph = run["graph"];
  EXPECT_EQ(graph["version"].as<uint64_t>(), 3u);
  EXPECT_NEAR(graph["mean_weights"][1][2].as<double>(), 0.71, 1e-6);
  ASSERT_EQ(graph["edges"].size(), 2u);
  EXPECT_EQ(graph["edges"][0]["from"].as<int>(), 0);
  EXPECT_EQ(graph["edges"][0]["to"].as<int>(), 1);
  EXPECT_NEAR(graph["edges"][0]["weight"].as<double>(), 0.93, 1e-6);
  EXPECT_EQ(graph["depths"][2].as<int>(), -1);
  // health as the display computes it
  ASSERT_EQ(doc["nodes"].size(), 3u);
  std::map<std::string, std::string> health;
  for (const Node& n : doc["nodes"].items())
    health[n["role"].as<std::string>() + std::to_string(n["id"].as<int>())] = n["health"].as<std::string>();
  EXPECT_EQ(health["learner0"], "alive");
  EXPECT_EQ(health["actor1"], "exited");
  EXPECT_EQ(health["actor2"], "LOST");
  EXPECT_EQ(doc["node_counts"]["lost"].as<int>(), 1);
  EXPECT_EQ(doc["processes"][0]["restarts"].as<int>(), 2);
  EXPECT_EQ(doc["events"][0].as<std::string>(), "[00:00:01] started");
  EXPECT_TRUE(doc["episode"].IsNull());
  // Unix times keep their seconds (a float's 7 digits would round them to 100 s)
  EXPECT_NEAR(doc["wall_time"].as<double>(), mon::WallTimeNow(), 5.0);
}

TEST(DashboardJsonTest, LearnerHistoryIsThinnedEvenlyAndEndsAtTheLatest) {
  mon::LearnerHistory history;
  history.max_points = 10;
  for (uint64_t i = 0; i < 1000; ++i) mon::Add(&history, {.updates = i});
  ASSERT_LE(history.points.size(), 10u);
  ASSERT_GE(history.points.size(), 5u);
  for (size_t k = 0; k < history.points.size(); ++k) EXPECT_EQ(history.points[k].updates, k * history.stride);
  EXPECT_EQ(history.latest->updates, 999u);
  mon::MonitorState state;
  state.runs["r1"].learner_history = history;
  const Node doc = Parse(DashboardJson(state, mon::Clock::now(), {}, {}));
  const Node updates = doc["runs"][0]["learner_history"]["updates"];
  EXPECT_EQ(updates.size(), history.points.size() + 1);
  EXPECT_EQ(updates[updates.size() - 1].as<uint64_t>(), 999u);
}

class RunFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("dashboard_folder_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A run folder as the launcher leaves it: its config, the three CSV files, a graph. The
  // rows span 61 s and the last learner row is `last_age_s` seconds old.
  void WriteRunFolder(double last_age_s = 1.5) {
    const config::Config config =
        config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                           {"run.total_env_steps=5000", "transport.run_id=folder-run"});
    std::ofstream(dir_ / "config.yaml") << config.effective_yaml;
    const double t0 = mon::WallTimeNow() - 60.5 - last_age_s;
    mon::CsvSink sink(dir_.string());
    auto eval = [](uint64_t version, uint64_t steps, float object, float subgoal) {
      rl::EvalReport e = Eval(version, steps, object);
      e.summary.entity_distance = {0.01f, object};
      e.summary.subgoal_success = {1.0f, subgoal};
      return e;
    };
    sink.Append("folder-run", eval(0, 0, 0.25f, 0.05f), t0);
    sink.Append("folder-run", eval(11, 1000, 0.2f, 0.3f), t0 + 20);
    sink.Append("folder-run", eval(23, 2000, 0.15f, 0.55f), t0 + 40);
    sink.Append("folder-run", eval(31, 3000, 0.1f, 0.7f), t0 + 60);
    for (int k = 0; k <= 60; ++k) {
      rl::NodeStatus learner = mon::testing::Node("learner", 0, rl::NodePhase::kTraining);
      learner.report.steps = 50 * static_cast<uint64_t>(k);
      sink.Append("folder-run", learner, t0 + k);
      rl::LearnerReport s;
      s.updates = 10 * static_cast<uint64_t>(k);
      s.transitions_inserted = 2000 + 50 * static_cast<uint64_t>(k);
      s.q_loss = 1.0f / static_cast<float>(k + 1);
      s.policy_loss = -0.5f;
      s.updates_per_second = 10;
      sink.Append("folder-run", s, t0 + k + 0.5);
    }
    sink.Append("folder-run", mon::testing::Node("actor", 0, rl::NodePhase::kTraining), t0 + 45);
    sink.Append("folder-run", mon::testing::Node("actor", 1, rl::NodePhase::kStopping), t0 + 50);
    sink.Append("folder-run", mon::testing::Node("actor", 1, rl::NodePhase::kStopping), t0 + 55, "exited");
    sink.Append("folder-run", mon::testing::Node("actor", 0, rl::NodePhase::kTraining), t0 + 55, "lost");
    graph_file::LearnedGraph graph = graph_file::AggregateGraph(2, {0.0, 0.46, 0.01, 0.0}, 0.06, /*action_entity=*/0);
    graph.version = 4;
    graph.entity_kinds = {0, 1};
    graph.action_correlation = {1.0, 0.4};
    graph_file::SaveGraph(graph, (dir_ / "graph.json").string());
  }

  fs::path dir_;
};

TEST_F(RunFolderTest, TheDocumentHoldsTheCsvFiguresRowByRow) {
  WriteRunFolder();
  RunFolderSource folder(dir_.string());
  ASSERT_TRUE(folder.Refresh(mon::Clock::now()));
  EXPECT_EQ(folder.skipped_rows(), 0u);
  const Node doc =
      Parse(DashboardJson(folder.state(), mon::Clock::now(), folder.render_options(), {.source = "run folder"}));
  ASSERT_EQ(doc["runs"].size(), 1u);
  const Node run = doc["runs"][0];
  EXPECT_EQ(run["run_id"].as<std::string>(), "folder-run");
  EXPECT_EQ(run["budget_env_steps"].as<uint64_t>(), 5000u);  // config.yaml's run.total_env_steps

  // every evaluation of eval.csv: the passive one apart, the others in order, figure by figure
  const auto eval_rows = ReadCsv(dir_ / "eval.csv");
  ASSERT_EQ(eval_rows.size(), 4u);
  EXPECT_EQ(run["passive"]["avg_object_distance"].as<double>(), Number(eval_rows[0].at("avg_object_distance")));
  ASSERT_EQ(run["evals"].size(), 3u);
  for (size_t i = 1; i < eval_rows.size(); ++i) {
    const Node e = run["evals"][i - 1];
    SCOPED_TRACE(i);
    EXPECT_EQ(e["env_steps"].as<uint64_t>(), std::stoull(eval_rows[i].at("env_steps")));
    EXPECT_EQ(e["policy_version"].as<uint64_t>(), std::stoull(eval_rows[i].at("policy_version")));
    EXPECT_FLOAT_EQ(e["avg_object_distance"].as<float>(), std::stof(eval_rows[i].at("avg_object_distance")));
    EXPECT_FLOAT_EQ(e["avg_distance"].as<float>(), std::stof(eval_rows[i].at("avg_distance")));
    EXPECT_FLOAT_EQ(e["success_rate"].as<float>(), std::stof(eval_rows[i].at("success_rate")));
    const std::vector<std::string> subgoals = Split(eval_rows[i].at("subgoal_success"), ';');
    ASSERT_EQ(e["subgoal_success"].size(), subgoals.size());
    for (size_t k = 0; k < subgoals.size(); ++k)
      EXPECT_FLOAT_EQ(e["subgoal_success"][k].as<float>(), std::stof(subgoals[k]));
  }
  // the learner: its last row, and the history of every row (61 rows: below the thinning)
  const auto learner_rows = ReadCsv(dir_ / "learner.csv");
  ASSERT_EQ(learner_rows.size(), 61u);
  EXPECT_EQ(run["learner"]["updates"].as<uint64_t>(), std::stoull(learner_rows.back().at("updates")));
  const Node history = run["learner_history"];
  ASSERT_EQ(history["updates"].size(), learner_rows.size());
  for (size_t i = 0; i < learner_rows.size(); ++i) {
    EXPECT_EQ(history["updates"][i].as<uint64_t>(), std::stoull(learner_rows[i].at("updates")));
    EXPECT_FLOAT_EQ(history["q_loss"][i].as<float>(), std::stof(learner_rows[i].at("q_loss")));
  }
  // env steps: the learner's training steps (from its node rows), not the inserts
  EXPECT_EQ(run["env_steps"].as<uint64_t>(), 3000u);  // the last eval's 3000 > the learner's 3000
  EXPECT_EQ(history["env_steps"][60].as<uint64_t>(), 3000u);
  EXPECT_EQ(history["env_steps"][10].as<uint64_t>(), 500u);
  // 50 steps a second in the rows' own times
  ASSERT_FALSE(run["env_steps_per_second"].IsNull());
  EXPECT_NEAR(run["env_steps_per_second"].as<double>(), 50.0, 1.0);
  // graph.json
  EXPECT_EQ(run["graph"]["version"].as<uint64_t>(), 4u);
  ASSERT_EQ(run["graph"]["edges"].size(), 1u);
  EXPECT_NEAR(run["graph"]["edges"][0]["weight"].as<double>(), 0.46, 1e-6);
  // nodes: the events of nodes.csv decide exited and lost
  std::map<std::string, std::string> health;
  for (const Node& n : doc["nodes"].items())
    health[n["role"].as<std::string>() + std::to_string(n["id"].as<int>())] = n["health"].as<std::string>();
  EXPECT_EQ(health["actor0"], "LOST");
  EXPECT_EQ(health["actor1"], "exited");
  EXPECT_EQ(health["learner0"], "alive");  // its last row is 2 s old
}

TEST_F(RunFolderTest, AStoppedRunHasNoRateAndItsSilentNodesAreLost) {
  WriteRunFolder(/*last_age_s=*/100);
  RunFolderSource folder(dir_.string());
  folder.Refresh(mon::Clock::now());
  const Node doc = Parse(DashboardJson(folder.state(), mon::Clock::now(), folder.render_options(), {}));
  EXPECT_TRUE(doc["runs"][0]["env_steps_per_second"].IsNull());
  EXPECT_TRUE(doc["runs"][0]["eta_s"].IsNull());
  EXPECT_EQ(doc["runs"][0]["env_steps"].as<uint64_t>(), 3000u);
  EXPECT_EQ(doc["node_counts"]["lost"].as<int>(), 2);  // the learner and actor 0
  EXPECT_EQ(doc["node_counts"]["exited"].as<int>(), 1);
  EXPECT_THAT(doc["title"].as<std::string>(), ::testing::Not(::testing::HasSubstr("finished")));
  std::ofstream(dir_ / "outcome.yaml")
      << "# how this run ended\nstate: finished\nexit_code: 0\nreason: \"the budget is done\"\n";
  ASSERT_TRUE(folder.Refresh(mon::Clock::now()));
  EXPECT_THAT(folder.render_options().title, ::testing::HasSubstr("(finished: the budget is done)"));
}

TEST_F(RunFolderTest, RefreshSeesNewRowsAndIgnoresAHalfWrittenLine) {
  WriteRunFolder();
  RunFolderSource folder(dir_.string());
  folder.Refresh(mon::Clock::now());
  EXPECT_FALSE(folder.Refresh(mon::Clock::now()));  // nothing changed
  {
    mon::CsvSink sink(dir_.string());
    sink.Append("folder-run", Eval(40, 4000, 0.05f), mon::WallTimeNow());
  }
  std::ofstream(dir_ / "eval.csv", std::ios::app) << "1.5,folder-run,0,41,1,45";  // no newline yet
  ASSERT_TRUE(folder.Refresh(mon::Clock::now()));
  const Node run = Parse(DashboardJson(folder.state(), mon::Clock::now(), folder.render_options(), {}))["runs"][0];
  ASSERT_EQ(run["evals"].size(), 4u);
  EXPECT_EQ(run["latest_eval"]["env_steps"].as<uint64_t>(), 4000u);
  EXPECT_EQ(folder.skipped_rows(), 0u);
}

TEST_F(RunFolderTest, AMalformedRowIsSkippedAndCounted) {
  WriteRunFolder();
  std::ofstream(dir_ / "eval.csv", std::ios::app) << "1.5,folder-run,0,notanumber,1,45,20,0.1,0.1,0,0,0;0,0;0\n";
  RunFolderSource folder(dir_.string());
  folder.Refresh(mon::Clock::now());
  EXPECT_EQ(folder.skipped_rows(), 1u);
  EXPECT_EQ(folder.state().runs.at("folder-run").evals.size(), 3u);
}

TEST(RunFolderSourceTest, RefusesAFolderWithoutRunFiles) {
  const fs::path empty = fs::path(::testing::TempDir()) / ("dashboard_empty_" + std::to_string(getpid()));
  fs::create_directories(empty);
  EXPECT_THROW(RunFolderSource(empty.string()), std::invalid_argument);
  EXPECT_THROW(RunFolderSource((empty / "missing").string()), std::invalid_argument);
  fs::remove_all(empty);
}

TEST(EpisodeMediaTest, TheNewestEpisodeWithItsMetricsAndOnlyMediaPaths) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("dashboard_media_" + std::to_string(getpid()));
  fs::remove_all(dir);
  EXPECT_FALSE(FindLatestEpisode(dir.string()));
  fs::create_directories(dir / "eval" / "episode-001");
  std::ofstream(dir / "eval" / "episode-000.gif") << "GIF89a";
  for (const char* frame : {"frame-00000.png", "frame-00001.png", "frame-00002.png"})
    std::ofstream(dir / "eval" / "episode-001" / frame) << "png";
  std::ofstream(dir / "eval" / "episodes.csv") << "episode,seed,status,avg_distance,video\n"
                                                  "0,7,ok,0.125,episode-000.gif\n1,8,ok,0.25,episode-001\n";
  fs::last_write_time(dir / "eval" / "episode-000.gif", fs::file_time_type::clock::now() - std::chrono::hours(1));
  const std::optional<EpisodeMedia> latest = FindLatestEpisode(dir.string());
  ASSERT_TRUE(latest);
  EXPECT_EQ(latest->name, "episode-001");
  EXPECT_EQ(latest->kind, "frames");
  EXPECT_EQ(latest->frames, 3);
  EXPECT_EQ(latest->metrics.at("avg_distance"), "0.25");
  const Node doc = Parse(DashboardJson({}, mon::Clock::now(), {}, {.episode = latest}));
  EXPECT_EQ(doc["episode"]["url"].as<std::string>(), "/media/eval/episode-001");
  EXPECT_EQ(doc["episode"]["frames"].as<int>(), 3);
  EXPECT_NEAR(doc["episode"]["modified"].as<double>(), latest->modified, 0.01);

  EXPECT_TRUE(IsEpisodeMediaPath("eval/episode-000.gif"));
  EXPECT_TRUE(IsEpisodeMediaPath("eval/episode-012.mp4"));
  EXPECT_TRUE(IsEpisodeMediaPath("eval/episode-001/frame-00002.png"));
  for (const char* bad : {"config.yaml", "eval/episodes.csv", "eval/../config.yaml", "../eval/episode-000.gif",
                          "/etc/passwd", "eval/episode-000.gif/../../checkpoint.srics", "eval/episode-1.gif"})
    EXPECT_FALSE(IsEpisodeMediaPath(bad)) << bad;
  fs::remove_all(dir);
}

TEST(HttpServerTest, ServesThePageTheLatestDocumentAndEpisodeMediaOnly) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("dashboard_server_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "eval");
  std::ofstream(dir / "eval" / "episode-000.gif") << "GIF89a-bytes";
  std::ofstream(dir / "config.yaml") << "secret: 1\n";
  HttpServer server({.port = 0, .run_dir = dir.string()});
  ASSERT_GT(server.port(), 0);
  httplib::Client client("127.0.0.1", server.port());
  auto state = client.Get("/api/state");
  ASSERT_TRUE(state);
  EXPECT_EQ(state->status, 503);  // nothing published yet
  server.Publish("{\"schema\":\"x\"}");
  state = client.Get("/api/state");
  ASSERT_TRUE(state);
  EXPECT_EQ(state->status, 200);
  EXPECT_EQ(state->body, "{\"schema\":\"x\"}");
  EXPECT_EQ(state->get_header_value("Content-Type"), "application/json");
  auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_THAT(page->body, ::testing::HasSubstr("<script src=\"dashboard.js\">"));
  auto script = client.Get("/dashboard.js");
  ASSERT_TRUE(script);
  EXPECT_THAT(script->body, ::testing::HasSubstr("api/state"));
  auto gif = client.Get("/media/eval/episode-000.gif");
  ASSERT_TRUE(gif);
  EXPECT_EQ(gif->status, 200);
  EXPECT_EQ(gif->body, "GIF89a-bytes");
  for (const char* bad : {"/media/config.yaml", "/media/eval/../config.yaml", "/media/eval/%2e%2e/config.yaml",
                          "/config.yaml", "/media/eval/episode-001.gif"}) {
    auto response = client.Get(bad);
    ASSERT_TRUE(response) << bad;
    EXPECT_EQ(response->status, 404) << bad;
    EXPECT_THAT(response->body, ::testing::Not(::testing::HasSubstr("secret"))) << bad;
  }
  fs::remove_all(dir);
}

TEST(HttpServerTest, ATakenPortIsABindErrorNamingThePort) {
  HttpServer first({.port = 0});
  try {
    HttpServer second({.port = first.port()});
    FAIL() << "a second server on port " << first.port();
  } catch (const BindError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("127.0.0.1:" + std::to_string(first.port())));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("in use"));
  }
  EXPECT_THROW(HttpServer({.bind = "192.0.2.1", .port = 0}), BindError);  // not this host's address
  EXPECT_THROW(ParseHttpPort("65536"), std::invalid_argument);
  EXPECT_THROW(ParseHttpPort("80x"), std::invalid_argument);
  EXPECT_EQ(ParseHttpPort("8080"), 8080);
}

TEST(DashboardTest, PublishesAtMostOncePerPeriodUnlessForced) {
  Dashboard dashboard({.port = 0, .source = "dds", .publish_period = std::chrono::seconds(1)});
  mon::MonitorState state;
  const auto t0 = mon::Clock::now();
  EXPECT_TRUE(dashboard.Update(state, t0, {}));
  EXPECT_FALSE(dashboard.Update(state, t0 + std::chrono::milliseconds(500), {}));
  EXPECT_TRUE(dashboard.Update(state, t0 + std::chrono::milliseconds(500), {}, /*force=*/true));
  EXPECT_TRUE(dashboard.Update(state, t0 + std::chrono::milliseconds(1600), {}));
  httplib::Client client("127.0.0.1", dashboard.port());
  auto response = client.Get("/api/state");
  ASSERT_TRUE(response);
  EXPECT_EQ(Parse(response->body)["source"].as<std::string>(), "dds");
}

}  // namespace
}  // namespace srics::dashboard
