#include "graph_service/service.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "common/links/in_memory_bus.h"
#include "tests/graph_service/toy_world.h"

namespace srics::graph_service {
namespace {

using testing::FeedSource;
using testing::RecordingSink;
using testing::ToySource;
using testing::ToyWorld;

config::GraphConfig TinyConfig() {
  config::GraphConfig c;
  c.episodes = 20;
  c.episode_steps = 10;
  c.window = 5;
  c.batch_windows = 4;
  c.hidden_dim = 4;
  c.mlp_hidden = 8;
  c.max_updates = 30;
  c.min_updates = 0;
  c.eval_every_updates = 10;
  c.stable_evaluations = 100;
  return c;
}

std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

// Feeds a fixed list of episodes, then closes; counts polls.
class ListSource : public EpisodeSource {
 public:
  explicit ListSource(std::vector<rl::Episode> episodes) : episodes_(std::move(episodes)) {}
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    ++polls;
    out->insert(out->end(), episodes_.begin(), episodes_.end());
    episodes_.clear();
    return false;
  }
  int polls = 0;

 private:
  std::vector<rl::Episode> episodes_;
};

TEST(GraphServiceTest, TrainsPublishesSavesAndRepublishesAfterRestart) {
  const std::string dir = FreshDir("service_restart");
  ToyWorld world({.num_pucks = 2, .static_pucks = {2}, .steps = 10});
  std::vector<rl::Episode> episodes;
  for (int i = 0; i < 25; ++i) episodes.push_back(world.RandomEpisode(i));
  // untrusted input: wrong mode is skipped, broken episodes are counted as dropped
  episodes[3].mode = rl::EpisodeMode::kTrain;
  episodes[4].states.pop_back();
  episodes[5].actions[0] = std::nanf("");
  ListSource source(episodes);
  RecordingSink sink;
  std::vector<Progress> seen;
  GraphService service(TinyConfig(), {.state_dir = dir, .seed = 3, .render_pictures = false}, &source, &sink,
                       [&](const Progress& p) { seen.push_back(p); });
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  ASSERT_EQ(sink.graphs.size(), 1u);
  const rl::GraphUpdate& g = sink.graphs[0];
  EXPECT_EQ(g.version, 1u);
  EXPECT_EQ(g.training_updates, 30u);
  EXPECT_EQ(g.episodes_used, 20u);
  EXPECT_EQ(g.graph.num_entities, 3);
  EXPECT_EQ(g.graph.action_entity, 0);
  EXPECT_EQ(service.progress().dropped, 2);
  EXPECT_EQ(service.progress().phase, Progress::Phase::kPublished);
  // progress went through collecting and training with held-out losses
  bool trained = false;
  for (const Progress& p : seen) trained |= p.phase == Progress::Phase::kTraining && p.held_out_loss > 0;
  EXPECT_TRUE(trained);
  ASSERT_TRUE(std::filesystem::exists(dir + "/graph.json"));

  // restart: the saved graph is re-published, nothing is collected or trained
  ListSource unused({});
  RecordingSink sink2;
  GraphService restarted(TinyConfig(), {.state_dir = dir, .seed = 3}, &unused, &sink2, {});
  ASSERT_EQ(restarted.Run(stop), 0);
  EXPECT_EQ(unused.polls, 0);
  ASSERT_EQ(sink2.graphs.size(), 1u);
  EXPECT_EQ(sink2.graphs[0].version, 1u);
  EXPECT_EQ(sink2.graphs[0].mean_weights, g.mean_weights);
  EXPECT_TRUE(SameStructure(sink2.graphs[0].graph, g.graph));
}

// Issue 38: the status a display shows during the graph phase says how far the phase is, of how
// much, and when it should end (training: at most max_updates, a stable graph ends it sooner).
TEST(GraphServiceTest, StatusesSayHowFarTheTrainingIsAndItsEta) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  std::vector<rl::Episode> episodes;
  for (int i = 0; i < 20; ++i) episodes.push_back(world.RandomEpisode(i));
  ListSource source(episodes);
  RecordingSink sink;
  GraphService service(TinyConfig(), {.seed = 3, .render_pictures = false, .status_period_s = 0}, &source, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  bool counted = false, eta = false;
  for (const rl::NodeReport& r : sink.statuses) {
    if (r.detail.rfind("training:", 0) != 0) continue;
    counted |= r.detail.find(" of at most 30 updates") != std::string::npos;
    eta |= r.detail.find(", ETA <= ") != std::string::npos;
  }
  EXPECT_TRUE(counted) << (sink.statuses.empty() ? "" : sink.statuses.back().detail);
  EXPECT_TRUE(eta) << (sink.statuses.empty() ? "" : sink.statuses.back().detail);
}

TEST(GraphServiceTest, CorruptedSavedGraphIsSetAsideAndLearnedAgain) {
  const std::string dir = FreshDir("service_corrupted");
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir + "/graph.json");
    out << "{\"format\": \"srics-interaction-graph\", \"num_ent";
  }
  ToySource source({.num_pucks = 2, .steps = 10}, 20, 7);
  RecordingSink sink;
  GraphService service(TinyConfig(), {.state_dir = dir, .seed = 1, .render_pictures = false}, &source, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  EXPECT_EQ(sink.graphs.size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/graph.json.rejected"));
  EXPECT_NO_THROW(LoadGraph(dir + "/graph.json"));
}

TEST(GraphServiceTest, StopsWithoutPublishingWhenTheSourceCloses) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  ListSource source({world.RandomEpisode(1), world.RandomEpisode(2)});
  RecordingSink sink;
  GraphService service(TinyConfig(), {}, &source, &sink, {});
  std::atomic<bool> stop{false};
  EXPECT_EQ(service.Run(stop), 1);
  EXPECT_TRUE(sink.graphs.empty());
  EXPECT_EQ(service.progress().episodes, 2);
}

TEST(GraphServiceTest, StableGraphEndsTrainingBeforeMaxUpdates) {
  config::GraphConfig c = TinyConfig();
  c.max_updates = 1000;
  c.stable_evaluations = 2;
  c.eval_every_updates = 5;
  c.min_updates = 10;
  c.warmup_updates = 0;  // graphs of the warm-up and the KL ramp never count as stable
  c.kl_ramp_updates = 0;
  ToySource source({.num_pucks = 2, .steps = 10}, 20, 3);
  RecordingSink sink;
  GraphService service(c, {.seed = 2}, &source, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  ASSERT_EQ(sink.graphs.size(), 1u);
  // the graph of a tiny model hardly changes within a few updates
  EXPECT_LT(sink.graphs[0].training_updates, 1000u);
  EXPECT_GE(sink.graphs[0].training_updates, 15u);
}

// The service stepped by hand on the in-memory bus: explore episodes published by an actor's
// end reach it, training episodes do not count, and the graph reaches every other end.
TEST(GraphServiceTest, StepsOnTheInMemoryBusUntilTheGraphReachesActorsAndLearner) {
  links::InMemoryBus bus;
  auto source = bus.GraphSourceEnd();
  auto sink = bus.GraphSinkEnd();
  auto actor = bus.ActorEnd(0);
  auto learner = bus.LearnerEnd();
  GraphService service(TinyConfig(), {.seed = 4, .render_pictures = false}, source.get(), sink.get(), {});
  ToyWorld world({.num_pucks = 2, .steps = 10});
  EXPECT_EQ(service.Step(), StepResult::kIdle);  // nothing published yet
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(actor->PublishEpisode(world.RandomEpisode(i)));
  rl::Episode train = world.RandomEpisode(99);
  train.mode = rl::EpisodeMode::kTrain;  // the learner's, not the graph service's
  ASSERT_TRUE(actor->PublishEpisode(train));
  EXPECT_EQ(service.Step(), StepResult::kWorked);
  EXPECT_EQ(service.progress().episodes, 10);
  EXPECT_EQ(service.progress().phase, Progress::Phase::kCollecting);
  for (int i = 10; i < 20; ++i) ASSERT_TRUE(actor->PublishEpisode(world.RandomEpisode(i)));
  int steps = 0;
  while (!service.published() && steps < 100) {
    EXPECT_NE(service.Step(), StepResult::kDone);
    ++steps;
    if (!service.published()) EXPECT_FALSE(actor->PollGraph().has_value()) << "a graph before the publication";
  }
  ASSERT_TRUE(service.published());
  EXPECT_EQ(service.progress().updates, 30);
  EXPECT_GE(steps, 3) << "each step does at most updates_per_step (10) GNN updates";
  const auto seen_by_actor = actor->PollGraph();
  ASSERT_TRUE(seen_by_actor.has_value());
  EXPECT_EQ(seen_by_actor->version, 1u);
  EXPECT_FALSE(actor->PollGraph().has_value()) << "the newest graph is delivered once";
  const auto seen_by_learner = learner->PollGraph();
  ASSERT_TRUE(seen_by_learner.has_value());
  EXPECT_EQ(seen_by_learner->graph.adjacency, service.published()->graph.adjacency);
  // after the publication the service only drains
  EXPECT_EQ(service.Step(), StepResult::kIdle);
}

// A service killed mid-training (the campaign's runs are stopped and resumed every session)
// resumes from its training state and ends with exactly the graph of an uninterrupted one.
config::GraphConfig ResumeConfig() {
  config::GraphConfig c = TinyConfig();
  c.max_updates = 40;
  c.warmup_updates = 15;  // the resume falls after Adam's restart at the warm-up's end
  c.kl_ramp_updates = 5;
  c.use_adam = true;
  c.restart_adam_after_warmup = true;
  return c;
}

ServiceOptions ShapedOptions(ToyWorld& world, const std::string& dir) {
  const rl::Episode e = world.RandomEpisode(0);
  ServiceOptions o{.state_dir = dir, .seed = 5, .render_pictures = false};
  o.shape = DatasetShape{e.layout, e.entity_kinds, e.action_dim};
  return o;
}

// The 20 episodes of the resume tests: `world`'s random ones from seed `first_seed` on.
std::vector<rl::Episode> ResumeEpisodes(ToyWorld& world, uint64_t first_seed) {
  std::vector<rl::Episode> episodes;
  for (uint64_t i = 0; i < 20; ++i) episodes.push_back(world.RandomEpisode(first_seed + i));
  return episodes;
}

// The graph a service never interrupted publishes from `episodes` (its state in a fresh
// folder `dir_name`): what a resumed one must end with.
rl::GraphUpdate UninterruptedGraph(ToyWorld& world, const std::vector<rl::Episode>& episodes,
                                   const std::string& dir_name) {
  ListSource all(episodes);
  RecordingSink sink;
  GraphService uninterrupted(ResumeConfig(), ShapedOptions(world, FreshDir(dir_name)), &all, &sink, {});
  std::atomic<bool> stop{false};
  EXPECT_EQ(uninterrupted.Run(stop), 0);
  EXPECT_EQ(sink.graphs.size(), 1u);
  return sink.graphs.empty() ? rl::GraphUpdate{} : sink.graphs[0];
}

TEST(GraphServiceTest, ResumesAnInterruptedTrainingAndEndsWithTheUninterruptedGraph) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  const std::vector<rl::Episode> episodes = ResumeEpisodes(world, 100);
  const rl::GraphUpdate reference = UninterruptedGraph(world, episodes, "service_resume_reference");

  const std::string dir = FreshDir("service_resume");
  {
    ListSource first(episodes);
    RecordingSink sink;
    GraphService killed(ResumeConfig(), ShapedOptions(world, dir), &first, &sink, {});
    while (killed.progress().updates < 20) ASSERT_NE(killed.Step(), StepResult::kDone);
    EXPECT_TRUE(sink.graphs.empty());
  }  // killed at 20 of 40 updates
  ASSERT_TRUE(std::filesystem::exists(dir + "/graph_training.srics"));

  ListSource nothing({});
  RecordingSink sink;
  GraphService resumed(ResumeConfig(), ShapedOptions(world, dir), &nothing, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(resumed.Run(stop), 0);
  EXPECT_EQ(nothing.polls, 0) << "the data set came from the training state";
  ASSERT_EQ(sink.graphs.size(), 1u);
  EXPECT_EQ(sink.graphs[0].training_updates, 40u);
  EXPECT_EQ(sink.graphs[0].episodes_used, 20u);
  // the same parameters, optimiser moments and batches: the same numbers, not just close ones
  EXPECT_EQ(sink.graphs[0].mean_weights, reference.mean_weights);
  EXPECT_EQ(sink.graphs[0].held_out_loss, reference.held_out_loss);
  EXPECT_FALSE(std::filesystem::exists(dir + "/graph_training.srics")) << "removed once graph.json is saved";
  EXPECT_TRUE(std::filesystem::exists(dir + "/graph.json"));
}

// graph.publish: lowest_held_out_loss (the default) publishes the evaluation after the warm-up
// and the KL ramp whose held-out loss was the lowest, not the last one (which `last` publishes); the stop is the
// same. A run killed after that evaluation and resumed publishes the same graph, number for
// number: the candidate is part of the saved training state.
TEST(GraphServiceTest, PublishesTheEvaluationOfTheLowestHeldOutLossWhenAsked) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  std::vector<rl::Episode> episodes;
  for (int i = 0; i < 20; ++i) episodes.push_back(world.RandomEpisode(400 + i));
  std::atomic<bool> stop{false};
  config::GraphConfig config = ResumeConfig();
  config.max_updates = 100;
  config.learning_rate = 0.1;  // a noisy descent: its lowest held-out loss comes before the end
  config.publish = config::GraphPublish::kLast;
  std::map<int64_t, double> settled_loss;  // evaluation -> held-out loss, after the warm-up and ramp
  auto record = [&](const Progress& p) {
    if (p.phase == Progress::Phase::kTraining && p.updates > config.warmup_updates + config.kl_ramp_updates)
      settled_loss[p.updates] = p.held_out_loss;
  };
  ListSource all(episodes);
  RecordingSink last;
  GraphService by_last(config, ShapedOptions(world, FreshDir("service_publish_last")), &all, &last, record);
  ASSERT_EQ(by_last.Run(stop), 0);
  ASSERT_EQ(last.graphs.size(), 1u);
  EXPECT_EQ(last.graphs[0].training_updates, 100u);
  ASSERT_EQ(settled_loss.size(), 8u);  // 30, 40, ..., 100
  const auto lowest = std::min_element(settled_loss.begin(), settled_loss.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
  ASSERT_NE(lowest->first, 100) << "the toy run's loss is lowest at its end: the test would show nothing";

  config.publish = config::GraphPublish::kLowestHeldOutLoss;
  ListSource again(episodes);
  RecordingSink chosen;
  GraphService by_loss(config, ShapedOptions(world, FreshDir("service_publish_lowest")), &again, &chosen, {});
  ASSERT_EQ(by_loss.Run(stop), 0);
  ASSERT_EQ(chosen.graphs.size(), 1u);
  EXPECT_EQ(chosen.graphs[0].training_updates, static_cast<uint64_t>(lowest->first));
  EXPECT_EQ(chosen.graphs[0].held_out_loss, lowest->second);
  EXPECT_EQ(by_loss.progress().updates, 100) << "the same stop";

  const std::string dir = FreshDir("service_publish_lowest_resumed");
  {
    ListSource first(episodes);
    RecordingSink sink;
    GraphService killed(config, ShapedOptions(world, dir), &first, &sink, {});
    while (killed.progress().updates < std::max<int64_t>(lowest->first, 60))
      ASSERT_NE(killed.Step(), StepResult::kDone);
  }
  ListSource nothing({});
  RecordingSink resumed;
  GraphService after(config, ShapedOptions(world, dir), &nothing, &resumed, {});
  ASSERT_EQ(after.Run(stop), 0);
  ASSERT_EQ(resumed.graphs.size(), 1u);
  EXPECT_EQ(resumed.graphs[0], chosen.graphs[0]);
}

TEST(GraphServiceTest, ResumesAnInterruptedCollectionWithTheEpisodesItHad) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  const std::vector<rl::Episode> episodes = ResumeEpisodes(world, 200);
  const rl::GraphUpdate reference = UninterruptedGraph(world, episodes, "service_collect_reference");
  std::atomic<bool> stop{false};

  const std::string dir = FreshDir("service_collect");
  {
    ListSource first_half({episodes.begin(), episodes.begin() + 12});
    RecordingSink sink;
    GraphService killed(ResumeConfig(), ShapedOptions(world, dir), &first_half, &sink, {});
    EXPECT_EQ(killed.Run(stop), 1);  // the source closed at 12 of 20
  }
  ListSource second_half({episodes.begin() + 12, episodes.end()});
  RecordingSink sink;
  GraphService resumed(ResumeConfig(), ShapedOptions(world, dir), &second_half, &sink, {});
  ASSERT_EQ(resumed.Run(stop), 0);
  ASSERT_EQ(sink.graphs.size(), 1u);
  EXPECT_EQ(sink.graphs[0].episodes_used, 20u);
  EXPECT_EQ(sink.graphs[0].mean_weights, reference.mean_weights);
}

TEST(GraphServiceTest, TrainingStateOfAnotherModelIsSetAsideAndLearnedAgain) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  const std::vector<rl::Episode> episodes = ResumeEpisodes(world, 300);
  const std::string dir = FreshDir("service_other_model");
  {
    ListSource source(episodes);
    RecordingSink sink;
    GraphService killed(ResumeConfig(), ShapedOptions(world, dir), &source, &sink, {});
    while (killed.progress().updates < 10) ASSERT_NE(killed.Step(), StepResult::kDone);
  }
  config::GraphConfig wider = ResumeConfig();
  wider.hidden_dim = 6;  // the saved GNN does not fit this one
  ListSource source(episodes);
  RecordingSink sink;
  GraphService restarted(wider, ShapedOptions(world, dir), &source, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(restarted.Run(stop), 0);
  EXPECT_TRUE(std::filesystem::exists(dir + "/graph_training.srics.rejected"));
  EXPECT_GT(source.polls, 0) << "learned again from fresh episodes";
  ASSERT_EQ(sink.graphs.size(), 1u);
  EXPECT_EQ(sink.graphs[0].training_updates, 40u);
}

// An environment with object_sets: explore episodes of every training combination feed one
// model, the published graph is over the catalogue, and an episode of another combination is
// dropped and counted.
TEST(GraphServiceTest, LearnsOneCatalogueGraphFromEveryTrainingCombination) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  const std::vector<std::vector<uint16_t>> sets = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}};
  // kinds in another order and a catalogue-sized episode are not training combinations
  std::vector<rl::Episode> episodes = {testing::AsCombination(world.RandomEpisode(90), 4, {0, 3, 1})};
  ToyWorld full({.num_pucks = 3, .steps = 10});
  episodes.push_back(full.RandomEpisode(91));
  for (int i = 0; i < 21; ++i) episodes.push_back(testing::AsCombination(world.RandomEpisode(i), 4, sets[i % 3]));
  ListSource source(episodes);
  RecordingSink sink;
  ServiceOptions o{.seed = 5, .render_pictures = false};
  const rl::Episode catalogue = full.RandomEpisode(0);
  o.shape = DatasetShape{catalogue.layout, catalogue.entity_kinds, catalogue.action_dim, sets};
  config::GraphConfig c = TinyConfig();
  c.episodes = 21;
  GraphService service(c, o, &source, &sink, nullptr);
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  EXPECT_EQ(service.progress().dropped, 2);
  ASSERT_EQ(sink.graphs.size(), 1u);
  const rl::GraphUpdate& g = sink.graphs[0];
  EXPECT_EQ(g.graph.num_entities, 4);
  EXPECT_EQ(g.structure.num_entities(), 4);
  EXPECT_EQ(rl::GraphMismatch(g.graph, 4), "");
  EXPECT_EQ(service.published()->entity_kinds, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(service.published()->graph.action_entity, 0);
  // the cut read-out swaps senders by position: refused for combinations
  config::GraphConfig cut = c;
  cut.readout = config::GraphReadout::kCut;
  EXPECT_THROW(GraphService(cut, o, &source, &sink, nullptr), std::invalid_argument);
}

// Refinement (graph.refine_after_publish) on the tiny model: training episodes taken in and
// trained on, others refused and counted, the state kept across a restart. (Whether it finds
// what random actions missed: refinement_test.cc.)
constexpr int kSteps = 20;

config::GraphConfig TinyRefiningConfig() {
  config::GraphConfig c = TinyConfig();
  c.episode_steps = kSteps;
  c.warmup_updates = 5;
  c.kl_ramp_updates = 5;
  c.min_updates = c.max_updates;
  c.refine_after_publish = true;
  c.refine_updates_per_episode = 3;
  return c;
}

ServiceOptions RefiningOptions(ToyWorld& world, const std::string& dir) {
  ServiceOptions o = ShapedOptions(world, dir);
  o.refine_episode_steps = kSteps;
  return o;
}

TEST(GraphServiceTest, RefinementKeepsItsStateAcrossARestartAndRefusesWhatDoesNotFit) {
  const std::string dir = FreshDir("service_refinement_restart");
  ToyWorld world({.num_pucks = 2, .ropes = {{1, 2}}, .rope_length = 0.3, .slide = 0.8, .steps = kSteps});
  FeedSource source;
  for (int i = 0; i < 20; ++i) source.queue.push_back(world.RandomEpisode(i));
  int taken = 0;
  {
    RecordingSink sink;
    GraphService service(TinyRefiningConfig(), RefiningOptions(world, dir), &source, &sink, {});
    std::atomic<bool> stop{false};
    ASSERT_EQ(service.Run(stop), 0);
    ASSERT_EQ(sink.graphs.size(), 1u);
    // the training state stays: the refinement goes on from it
    EXPECT_TRUE(std::filesystem::exists(dir + "/graph_training.srics"));
    rl::Episode short_one = world.PushEpisode(1, 1, 2, 0.27, 6);
    short_one.num_steps = kSteps - 1;  // not the run's training episode length
    short_one.states.resize(short_one.states.size() - short_one.layout.state_size());
    short_one.actions.resize(short_one.actions.size() - 2);
    source.queue.push_back(short_one);
    source.queue.push_back(world.RandomEpisode(77));  // explore episodes are the first graph's
    for (int i = 0; i < 30; ++i) source.queue.push_back(world.PushEpisode(100 + i, 1, 2, 0.27, 6));
    while (!source.queue.empty()) service.Step();
    for (int i = 0; i < 50; ++i) service.Step();  // the updates owed to the last episodes
    EXPECT_EQ(service.progress().refine_episodes, 30);
    EXPECT_EQ(service.progress().dropped, 1);
    EXPECT_NE(service.progress().last_drop_reason.find("steps"), std::string::npos)
        << service.progress().last_drop_reason;
    EXPECT_EQ(service.progress().updates, 30 + 30 * 3) << "refine_updates_per_episode per training episode";
    taken = service.progress().refine_episodes;
  }  // killed; its state was saved at the last evaluation (update 120)
  FeedSource nothing;
  RecordingSink sink;
  GraphService restarted(TinyRefiningConfig(), RefiningOptions(world, dir), &nothing, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(restarted.Run(stop), 0);
  ASSERT_EQ(sink.graphs.size(), 1u) << "the saved graph is re-published, not learned again";
  EXPECT_EQ(sink.graphs[0].version, 1u);
  EXPECT_TRUE(restarted.progress().refining);
  EXPECT_EQ(restarted.progress().refine_episodes, taken);
  EXPECT_EQ(restarted.progress().updates, 120);
  // and it goes on taking training episodes in
  nothing.queue.push_back(world.PushEpisode(500, 2, 1, 0.27, 6));
  restarted.Step();
  EXPECT_EQ(restarted.progress().refine_episodes, taken + 1);
}

}  // namespace
}  // namespace srics::graph_service
