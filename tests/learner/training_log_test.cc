// train.csv: the selectivity of training episodes, with the episode's own ancestor set and with
// the table's graph (the same for every method), against values computed by hand.

#include "learner/training_log.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace srics::learner {
namespace {

namespace fs = std::filesystem;

// The arm and two pucks (no identifier one-hot: K = 0, so each entity is x, y). One step: the
// arm and puck 1 move 0.1 m along x, puck 2 stays. The subgoal is puck 1's.
rl::Episode PushEpisode(uint64_t own_ancestor_mask) {
  rl::Episode e;
  e.layout = {.num_entities = 3, .num_kinds = 0, .velocities = false};
  e.entity_kinds = {0, 1, 2};
  e.num_steps = 1;
  e.states = {0.0f, 0.0f, 0.1f, 0.5f, 0.4f, 0.5f,   // t = 0
              0.1f, 0.0f, 0.2f, 0.5f, 0.4f, 0.5f};  // t = 1
  e.actions = {1.0f, 0.0f};
  e.subgoal_entity = 1;
  e.goal = {0.25f, 0.5f};
  e.ancestor_mask = own_ancestor_mask;
  e.mode = rl::EpisodeMode::kTrain;
  return e;
}

std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

TEST(TrainingLogTest, SelectivityWithTheEpisodesOwnAncestorsAndWithTheTableGraph) {
  TrainingLogOptions options;
  options.table_graph = rl::InteractionGraph::Star(3);  // action -> arm -> pucks 1, 2
  TrainingLog log(options);
  // SMORL's view: no ancestors. The arm (0.1) counts as an independent mover beside puck 2 (0):
  // own 0.1 / (0.1 + mean(0.1, 0)) = 2/3. With the table's graph the arm is puck 1's ancestor:
  // own 0.1 / (0.1 + 0) = 1.
  const auto smorl = log.Measure(PushEpisode(0));
  ASSERT_TRUE(smorl);
  EXPECT_NEAR(smorl->selectivity, 2.0 / 3.0, 1e-6);
  EXPECT_NEAR(smorl->table_graph_selectivity, 1.0, 1e-6);
  EXPECT_NEAR(smorl->subgoal_distance, 0.05, 1e-6);
  // SRICS's view with the right graph: both measures agree
  const auto srics = log.Measure(PushEpisode(0b001));
  ASSERT_TRUE(srics);
  EXPECT_NEAR(srics->selectivity, 1.0, 1e-6);
  EXPECT_NEAR(srics->table_graph_selectivity, 1.0, 1e-6);

  // without a table graph the column stays undefined
  const auto none = TrainingLog(TrainingLogOptions{}).Measure(PushEpisode(0));
  ASSERT_TRUE(none);
  EXPECT_LT(none->table_graph_selectivity, 0);

  // kinds the catalogue does not have: undefined, no throw (the learner refuses the episode)
  rl::Episode foreign = PushEpisode(0);
  foreign.entity_kinds = {0, 1, 7};
  const auto odd = log.Measure(foreign);
  ASSERT_TRUE(odd);
  EXPECT_LT(odd->table_graph_selectivity, 0);
}

// A tied pair attempted as one (graph.object_ties: joint): pucks 1 and 2 with a goal each; the
// episode's distance is the farther puck's, its own motion both pucks' (puck 1's 0.1), the arm
// its ancestor. Measured as a single subgoal, the 4-float goal is not counted.
TEST(TrainingLogTest, APairIsMeasuredAsOneSubgoalOfBothObjects) {
  TrainingLogOptions options;
  options.table_graph = rl::InteractionGraph::Star(3);
  TrainingLog log(options);
  rl::Episode pair = PushEpisode(0b101);  // puck 1's ancestors: the arm and its partner 2
  pair.goal = {0.25f, 0.5f, 0.4f, 0.7f};  // puck 1 ends 0.05 m from its goal, puck 2 0.2 m
  const auto figures = log.Measure(pair, 2);
  ASSERT_TRUE(figures);
  EXPECT_NEAR(figures->subgoal_distance, 0.2, 1e-6);
  // own 0.1 (puck 1) + 0 (puck 2); the arm an ancestor: nothing independent moved
  EXPECT_NEAR(figures->selectivity, 1.0, 1e-6);
  EXPECT_NEAR(figures->table_graph_selectivity, 1.0, 1e-6);
  EXPECT_FALSE(log.Measure(pair));  // no partner: the goal's size does not fit
}

TEST(TrainingLogTest, RowsCarryBothMeasuresAndAnOldFileKeepsItsRowsOnResume) {
  const fs::path dir = fs::temp_directory_path() / ("srics_training_log_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path path = dir / "train.csv";
  // a file of a run started before the table-graph columns existed
  std::ofstream(path)
      << "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success\n"
      << "1.0,5000,10,0.3,10,0.2,0.1\n"
      << "2.0,10000,10,0.4,10,0.15,0.2\n";
  TrainingLogOptions options;
  options.path = path.string();
  options.every_env_steps = 5000;
  options.table_graph = rl::InteractionGraph::Star(3);
  {
    TrainingLog log(options);
    log.ResumeAt(5000);  // the checkpoint was at 5000: the 10000 row is trained again
    log.Add(*log.Measure(PushEpisode(0)));
    log.Add(*log.Measure(PushEpisode(0)));
    log.Advance(10000);
  }
  const std::vector<std::string> lines = Lines(path);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success,"
            "table_graph_selectivity,table_graph_selectivity_episodes");
  EXPECT_EQ(lines[1], "1.0,5000,10,0.3,10,0.2,0.1,,");
  const std::vector<std::string> row = Fields(lines[2]);
  ASSERT_EQ(row.size(), 9u) << lines[2];
  EXPECT_EQ(row[1], "10000");
  EXPECT_EQ(row[2], "2");
  EXPECT_NEAR(std::stod(row[3]), 2.0 / 3.0, 1e-5);
  EXPECT_NEAR(std::stod(row[7]), 1.0, 1e-6);
  EXPECT_EQ(row[8], "2");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace srics::learner
