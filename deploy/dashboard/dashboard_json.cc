#include "deploy/dashboard/dashboard_json.h"

#include <algorithm>
#include <chrono>

#include "common/transport/wire.h"
#include "deploy/dashboard/json_writer.h"
#include "deploy/monitor/csv_sink.h"

namespace srics::dashboard {
namespace {

namespace mon = srics::monitor;
namespace tr = srics::transport;

double Seconds(mon::Clock::duration d) { return std::chrono::duration<double>(d).count(); }

template <typename V>
void Floats(JsonWriter* json, const std::vector<V>& values) {
  json->BeginArray();
  for (V v : values) json->Number(v);
  json->EndArray();
}

void Eval(JsonWriter* json, const rl::EvalReport& e) {
  const rl::EvaluationSummary& s = e.summary;
  json->BeginObject();
  json->Key("actor_id").Unsigned(e.actor_id);
  json->Key("policy_version").Unsigned(e.policy_version);
  json->Key("graph_version").Unsigned(e.graph_version);
  json->Key("env_steps").Unsigned(e.env_steps);
  json->Key("episodes").Unsigned(static_cast<uint32_t>(s.episodes));  // as the wire counts them
  json->Key("avg_distance").Number(s.avg_distance);
  json->Key("avg_object_distance").Number(s.avg_object_distance);
  json->Key("success_rate").Number(s.success_rate);
  json->Key("selectivity").Number(s.selectivity);
  json->Key("entity_distance");
  Floats(json, s.entity_distance);
  json->Key("subgoal_success");
  Floats(json, s.subgoal_success);
  json->EndObject();
}

void Learner(JsonWriter* json, const mon::RunView& run, mon::Clock::time_point now) {
  if (!run.learner) {
    json->Null();
    return;
  }
  const rl::LearnerReport& s = *run.learner;
  json->BeginObject();
  json->Key("updates").Unsigned(s.updates);
  json->Key("transitions_inserted").Unsigned(s.transitions_inserted);
  json->Key("training_env_steps").Unsigned(s.training_env_steps);
  json->Key("replay_size").Unsigned(s.replay_size);
  json->Key("episodes_accepted").Unsigned(s.episodes_accepted);
  json->Key("episodes_rejected").Unsigned(s.episodes_rejected);
  json->Key("policy_version").Unsigned(s.policy_version);
  json->Key("q_loss").Number(s.q_loss);
  json->Key("policy_loss").Number(s.policy_loss);
  json->Key("alpha").Number(s.alpha);
  json->Key("entropy").Number(s.entropy);
  json->Key("mean_reward").Number(s.mean_reward);
  json->Key("updates_per_second").Number(s.updates_per_second);
  json->Key("inserts_per_second").Number(s.inserts_per_second);
  json->Key("age_s").Number(Seconds(now - run.learner_received));
  json->EndObject();
}

void LearnerHistory(JsonWriter* json, const mon::LearnerHistory& history) {
  std::vector<mon::LearnerPoint> points = history.points;
  if (history.latest && (points.empty() || points.back().updates != history.latest->updates ||
                         points.back().env_steps != history.latest->env_steps))
    points.push_back(*history.latest);
  auto column = [&](const char* name, auto field) {
    json->Key(name).BeginArray();
    for (const mon::LearnerPoint& p : points) json->Number(static_cast<double>(field(p)));
    json->EndArray();
  };
  json->BeginObject();
  column("updates", [](const mon::LearnerPoint& p) { return p.updates; });
  column("env_steps", [](const mon::LearnerPoint& p) { return p.env_steps; });
  column("q_loss", [](const mon::LearnerPoint& p) { return p.q_loss; });
  column("policy_loss", [](const mon::LearnerPoint& p) { return p.policy_loss; });
  column("alpha", [](const mon::LearnerPoint& p) { return p.alpha; });
  column("entropy", [](const mon::LearnerPoint& p) { return p.entropy; });
  column("mean_reward", [](const mon::LearnerPoint& p) { return p.mean_reward; });
  column("updates_per_second", [](const mon::LearnerPoint& p) { return p.updates_per_second; });
  column("inserts_per_second", [](const mon::LearnerPoint& p) { return p.inserts_per_second; });
  json->EndObject();
}

void Graph(JsonWriter* json, const mon::RunView& run, mon::Clock::time_point now) {
  if (!run.graph) {
    json->Null();
    return;
  }
  const rl::GraphUpdate& g = *run.graph;
  const size_t n = static_cast<size_t>(g.graph.num_entities);
  auto at = [n](const auto& matrix, size_t i, size_t j) -> double {
    const size_t k = i * n + j;
    return k < matrix.size() ? static_cast<double>(matrix[k]) : 0.0;
  };
  json->BeginObject();
  json->Key("version").Unsigned(g.version);
  json->Key("num_entities").Unsigned(n);
  json->Key("action_entity").Integer(g.graph.action_entity);
  json->Key("threshold").Number(g.threshold);
  json->Key("held_out_loss").Number(g.held_out_loss);
  json->Key("training_updates").Unsigned(g.training_updates);
  json->Key("episodes_used").Unsigned(g.episodes_used);
  json->Key("edge_count").Unsigned(mon::EdgeCount(g));
  json->Key("mean_weights").BeginArray();
  for (size_t i = 0; i < n; ++i) {
    json->BeginArray();
    for (size_t j = 0; j < n; ++j) json->Number(at(g.mean_weights, i, j));
    json->EndArray();
  }
  json->EndArray();
  json->Key("edges").BeginArray();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j || at(g.graph.adjacency, i, j) == 0) continue;
      json->BeginObject().Key("from").Unsigned(i).Key("to").Unsigned(j);
      json->Key("weight").Number(at(g.mean_weights, i, j)).EndObject();
    }
  json->EndArray();
  json->Key("depths").BeginArray();
  for (int d : g.structure.depth) json->Integer(d);
  json->EndArray();
  json->Key("age_s").Number(Seconds(now - run.graph_received));
  json->EndObject();
}

void Run(JsonWriter* json, const std::string& id, const mon::RunView& run, mon::Clock::time_point now,
         const mon::RenderOptions& options, std::chrono::milliseconds lost_after) {
  const uint64_t steps = mon::EnvSteps(run);
  const uint64_t budget = mon::BudgetEnvSteps(run) > 0 ? mon::BudgetEnvSteps(run) : options.total_env_steps;
  // a rate (and an ETA) only while the learner reports: not for a stopped run's folder
  const bool reporting = run.learner && now - run.learner_received <= lost_after;
  const std::optional<double> rate = reporting ? mon::EnvStepRate(run) : std::nullopt;
  json->BeginObject();
  json->Key("run_id").String(id);
  json->Key("env_steps").Unsigned(steps);
  json->Key("budget_env_steps").Unsigned(budget);
  json->Key("env_steps_per_second");
  rate ? json->Number(*rate) : json->Null();
  json->Key("eta_s");
  if (rate && *rate > 0 && budget > steps)
    json->Number(static_cast<double>(budget - steps) / *rate);
  else
    json->Null();
  json->Key("learner");
  Learner(json, run, now);
  json->Key("learner_history");
  LearnerHistory(json, run.learner_history);
  json->Key("passive");
  run.passive ? Eval(json, *run.passive) : (void)json->Null();
  json->Key("latest_eval");
  const rl::EvalReport* latest = mon::LatestEval(run);
  latest ? Eval(json, *latest) : (void)json->Null();
  json->Key("evals").BeginArray();
  for (const rl::EvalReport& e : run.evals) Eval(json, e);
  json->EndArray();
  json->Key("graph");
  Graph(json, run, now);
  json->Key("weights");
  if (run.weights) {
    json->BeginObject();
    json->Key("version").Unsigned(run.weights->version);
    json->Key("update_count").Unsigned(run.weights->update_count);
    json->Key("num_parameters").Unsigned(run.weights->num_parameters);
    json->Key("age_s").Number(Seconds(now - run.weights->received));
    json->EndObject();
  } else {
    json->Null();
  }
  json->EndObject();
}

void Nodes(JsonWriter* json, const mon::MonitorState& state, mon::Clock::time_point now,
           const mon::RenderOptions& options) {
  size_t counts[4] = {};
  json->Key("nodes").BeginArray();
  for (const auto& [key, node] : state.nodes) {
    if (!mon::Shown(key.run_id, options)) continue;
    const mon::NodeHealth health = mon::HealthOf(state, node, now);
    ++counts[static_cast<int>(health)];
    const rl::NodeStatus& s = node.status;
    const rl::NodeReport& r = s.report;
    json->BeginObject();
    json->Key("run_id").String(key.run_id);
    json->Key("role").String(key.role);
    json->Key("id").Unsigned(key.node_id);
    json->Key("host").String(s.host);
    json->Key("pid").Integer(s.pid);
    json->Key("state").String(rl::NodePhaseName(r.phase));
    json->Key("health").String(mon::NodeHealthName(health));
    json->Key("policy_version").Unsigned(r.policy_version);
    json->Key("graph_version").Unsigned(r.graph_version);
    json->Key("env_steps").Unsigned(r.steps);
    json->Key("dropped_samples").Unsigned(r.dropped);
    json->Key("uptime_s").Number(static_cast<double>(s.uptime_ms) / 1000.0);
    json->Key("last_seen_s").Number(Seconds(now - node.last_seen));
    json->Key("detail").String(r.detail);
    json->EndObject();
  }
  json->EndArray();
  json->Key("node_counts").BeginObject();
  for (mon::NodeHealth h :
       {mon::NodeHealth::kAlive, mon::NodeHealth::kQuiet, mon::NodeHealth::kExited, mon::NodeHealth::kLost}) {
    std::string name = mon::NodeHealthName(h);
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    json->Key(name).Unsigned(counts[static_cast<int>(h)]);
  }
  json->EndObject();
  json->Key("dropped_samples").Unsigned(state.dropped_samples);
}

void Episode(JsonWriter* json, const std::optional<EpisodeMedia>& episode) {
  if (!episode) {
    json->Null();
    return;
  }
  json->BeginObject();
  json->Key("name").String(episode->name);
  json->Key("kind").String(episode->kind);
  json->Key("url").String("/media/" + episode->path);
  json->Key("frames").Integer(episode->frames);
  json->Key("modified").Number(episode->modified, 15);
  json->Key("metrics").BeginObject();
  for (const auto& [column, value] : episode->metrics) json->Key(column).String(value);
  json->EndObject();
  json->EndObject();
}

}  // namespace

std::string DashboardJson(const mon::MonitorState& state, mon::Clock::time_point now, const mon::RenderOptions& options,
                          const JsonContext& context) {
  JsonWriter json;
  json.BeginObject();
  json.Key("schema").String("srics-dashboard/1");
  json.Key("title").String(options.title);
  json.Key("source").String(context.source);
  json.Key("run_dir").String(context.run_dir);
  json.Key("poll_ms").Integer(context.poll_ms);
  json.Key("wall_time").Number(mon::WallTimeNow(), 15);
  json.Key("elapsed_s");
  options.elapsed_s >= 0 ? json.Number(options.elapsed_s) : json.Null();
  json.Key("max_wall_minutes").Number(options.max_wall_minutes);
  // the runs the display lists, in its order
  const std::vector<std::string> run_ids = mon::ShownRunIds(state, options);
  static const mon::RunView kEmpty;
  json.Key("runs").BeginArray();
  for (const std::string& id : run_ids) {
    auto it = state.runs.find(id);
    Run(&json, id, it == state.runs.end() ? kEmpty : it->second, now, options, state.lost_after);
  }
  json.EndArray();
  Nodes(&json, state, now, options);
  json.Key("processes").BeginArray();
  for (const mon::ProcessRow& p : options.processes) {
    json.BeginObject();
    json.Key("name").String(p.name);
    json.Key("pid").Integer(p.pid);
    json.Key("state").String(p.state);
    json.Key("restarts").Unsigned(p.restarts);
    json.Key("last_exit").String(p.last_exit);
    json.EndObject();
  }
  json.EndArray();
  json.Key("events").BeginArray();
  for (const std::string& event : options.events) json.String(event);
  json.EndArray();
  json.Key("episode");
  Episode(&json, context.episode);
  json.EndObject();
  return json.Take();
}

}  // namespace srics::dashboard
