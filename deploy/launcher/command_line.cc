#include "deploy/launcher/command_line.h"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/cli/cli.h"
#include "deploy/eval/eval_studies.h"

namespace srics::launcher {

namespace {

// --display auto|live|plain|none (srics run, srics sweep)
void AddDisplayOption(CLI::App& app, DisplayMode* display, const std::string& help) {
  static const std::map<std::string, DisplayMode> kModes = {{"auto", DisplayMode::kAuto},
                                                            {"live", DisplayMode::kLive},
                                                            {"plain", DisplayMode::kPlain},
                                                            {"none", DisplayMode::kNone}};
  app.add_option("--display", *display, help)
      ->transform(CLI::CheckedTransformer(kModes).description(""))
      ->type_name("MODE")
      ->default_str("auto");
}

std::vector<std::string> SplitList(const std::string& flag, const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (item.empty()) throw std::invalid_argument(flag + ": an empty item in '" + text + "'");
    items.push_back(item);
  }
  if (items.empty()) throw std::invalid_argument(flag + " needs at least one value");
  return items;
}

uint64_t ParseNumber(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || end == text.c_str() || *end != '\0')
    throw std::invalid_argument(flag + ": expected non-negative integers, got '" + text + "'");
  return value;
}

// "1,3,5-7" -> 1, 3, 5, 6, 7 (--seeds, --ids)
std::vector<uint64_t> ParseNumbers(const std::string& flag, const std::string& text) {
  std::vector<uint64_t> numbers;
  for (const std::string& item : SplitList(flag, text)) {
    const size_t dash = item.find('-', 1);
    if (dash == std::string::npos) {
      numbers.push_back(ParseNumber(flag, item));
      continue;
    }
    const uint64_t first = ParseNumber(flag, item.substr(0, dash)), last = ParseNumber(flag, item.substr(dash + 1));
    if (last < first || last - first > 1000) throw std::invalid_argument(flag + ": bad range '" + item + "'");
    for (uint64_t n = first; n <= last; ++n) numbers.push_back(n);
  }
  return numbers;
}

template <typename T>
void RefuseDuplicates(const std::string& flag, const std::vector<T>& values) {
  std::set<T> seen;
  for (const T& v : values) {
    if (!seen.insert(v).second) {
      std::ostringstream text;
      text << flag << " lists " << v << " twice";
      throw std::invalid_argument(text.str());
    }
  }
}

// ---- srics run
struct RunText {
  std::string roles, ids;  // --roles, --ids as given
};

void AddRunOptions(CLI::App& app, LaunchOptions* o, RunText* text) {
  app.description(
      "one training run on this machine: the graph service, the learner and the actors as processes over DDS\n"
      "(or --in-process), one live display, restarts of crashed processes; the run folder's outcome.yaml says\n"
      "how it ended. Exit codes: 0 run finished, 1 a role failed for good, 2 bad arguments/config, 130 interrupted");
  app.add_option("CONFIG", o->config_file,
                 "the run's config (e.g. deploy/configs/default.yaml; installed: default.yaml finds "
                 "<prefix>/share/srics-dds/configs/default.yaml)")
      ->required()
      ->transform(cli::InstalledConfig());
  app.add_flag("--in-process", o->in_process,
               "the same loops in one process, wired in memory (no DDS): deterministic, the same run folder; one "
               "thread, or the learner on a second (run.in_process_threads: 2)");
  app.add_option("--actors", o->actors, "actor processes (default: actors.count of the config)")
      ->check(cli::Integer(1))
      ->default_str("");
  cli::AddSetOption(app, &o->overrides, "override a config value (recorded in the run folder's config.yaml)");
  app.add_option("--run-dir", o->run_dir,
                 "the run folder (default <run.output_dir>/<run.name>-<timestamp>); an existing one is continued: the "
                 "learner resumes from its checkpoint, with the same config")
      ->type_name("DIR");
  app.add_flag("--allow-config-change", o->allow_config_change,
               "continue a run folder with a changed config (the change is recorded in its config-changes.log, the old "
               "config.yaml kept beside it)");
  app.add_option("--bin-dir", o->bin_dir,
                 "where srics-graph, srics-learner, srics-actor are (default: beside this program, or its build tree)")
      ->type_name("DIR");
  AddDisplayOption(app, &o->display,
                   "live (refreshing screen), plain (a line every 10 s), none, auto (live on a terminal)");
  app.add_option("--stop-timeout", o->stop_timeout_s, "seconds between SIGINT and SIGKILL when stopping")
      ->check(cli::Number(0));
  app.add_option(
         "--final-eval-grace", o->final_eval_grace_s,
         "once the learner finished, seconds to wait for the actors' final evaluation and exit before stopping them")
      ->check(cli::Number(0));
  app.add_option("--label", o->label, "shown in the display's title (srics sweep: which run of how many)")
      ->type_name("TEXT");
  CLI::Option* http =
      app.add_option("--http", o->http_port,
                     "serve the live web dashboard on PORT (0: any free port; 127.0.0.1 only unless --http-bind)")
          ->check(cli::Integer(0, 65535))
          ->type_name("PORT")
          ->default_str("");
  app.add_option("--http-bind", o->http_bind, "the address to serve the dashboard on (0.0.0.0 = every interface)")
      ->needs(http)
      ->type_name("ADDR");
  app.add_option("--roles", text->roles,
                 "this host's share of a run on several hosts: graph, learner, actor, comma-separated (default: all); "
                 "every host needs the same explicit transport.run_id")
      ->type_name("LIST");
  app.add_option("--ids", text->ids,
                 "with --roles actor: this host's actor ids, comma-separated, A-B for a range "
                 "(default: 0 to actors.count - 1)")
      ->type_name("LIST");
}

void FinishRunOptions(LaunchOptions* o, const RunText& text) {
  if (o->actors > 0) o->overrides.push_back("actors.count=" + std::to_string(o->actors));
  if (!text.roles.empty()) {
    o->roles = SplitList("--roles", text.roles);
    for (const std::string& role : o->roles)
      if (role != "graph" && role != "learner" && role != "actor")
        throw std::invalid_argument("--roles: expected graph, learner or actor, got '" + role + "'");
    RefuseDuplicates("--roles", o->roles);
  }
  if (!text.ids.empty()) {
    if (std::find(o->roles.begin(), o->roles.end(), "actor") == o->roles.end())
      throw std::invalid_argument("--ids: only with --roles including actor (the actors of this host)");
    for (uint64_t id : ParseNumbers("--ids", text.ids)) {
      if (id > 100000) throw std::invalid_argument("--ids: expected actor ids up to 100000, got " + std::to_string(id));
      o->actor_ids.push_back(static_cast<int>(id));
    }
    RefuseDuplicates("--ids", o->actor_ids);
  }
}

// ---- srics sweep
struct SweepText {
  std::string methods, seeds;
};

void AddSweepOptions(CLI::App& app, SweepOptions* o, SweepText* text) {
  app.description(
      "every method with every seed, one run folder each (DIR/<method>-seed<seed>), one after another; the same\n"
      "command again resumes: finished runs are skipped, the others continue from their checkpoints.\n"
      "Exit codes: 0 every run finished, 1 a run failed (the others ran; run again to retry),\n"
      "2 bad arguments/config or another grid in DIR, 130 interrupted");
  app.add_option("CONFIG", o->config_file, "the config every run starts from")
      ->required()
      ->transform(cli::InstalledConfig());
  app.add_option("--methods", text->methods, "run.method names, comma-separated (srics, smorl, sac_her, ...)")
      ->required()
      ->type_name("LIST");
  app.add_option("--seeds", text->seeds, "run.seed values, comma-separated; A-B for a range (1-3)")
      ->required()
      ->type_name("LIST");
  cli::AddSetOption(app, &o->overrides, "a config override for every run");
  app.add_option("--out", o->out_dir,
                 "the sweep folder (default <run.output_dir>/<run.name>-sweep); DIR/sweep.yaml records the grid and "
                 "another grid into the same folder is refused")
      ->type_name("DIR");
  app.add_flag("--in-process", o->in_process, "each run in one process (srics run --in-process)");
  app.add_option("--parallel", o->parallel, "runs at a time (one per core at most)")->check(cli::Integer(1, 64));
  AddDisplayOption(
      app, &o->display,
      "each run's display: live, plain, none, auto (with --parallel > 1: plain lines in DIR/logs/<run>.out, "
      "the sweep prints each run's latest line every 10 s)");
  app.add_option("--stop-timeout", o->stop_timeout_s,
                 "on Ctrl-C, seconds a run has to checkpoint and exit before it is killed")
      ->check(cli::Number(0));
  app.add_option("--program", o->program, "the srics program to run (default: this one)")->group("");
}

void FinishSweepOptions(SweepOptions* o, const SweepText& text) {
  o->methods = SplitList("--methods", text.methods);
  o->seeds = ParseNumbers("--seeds", text.seeds);
  RefuseDuplicates("--methods", o->methods);
  RefuseDuplicates("--seeds", o->seeds);
}

// ---- srics compare
void AddCompareOptions(CLI::App& app, analysis::CompareOptions* o) {
  app.description(
      "figures and a table of final figures from sweeps: per environment <env>-distance.png,\n"
      "<env>-object_distance.png, <env>-subgoal_success.png, <env>-selectivity.png, <env>-undone.png (mean over\n"
      "seeds, band ±1 sd),\n"
      "<env>-<run>-graph.png; results.md: final figures, mean ± std over seeds, each run's learned graph against the\n"
      "one by construction");
  app.add_option("DIR", o->dirs, "sweep folders (srics sweep) or run folders; their eval.csv and train.csv are read")
      ->required();
  app.add_option("--out", o->out_dir,
                 "where the figures and results.md go (default DIR/compare for one DIR, ./compare for several)")
      ->type_name("DIR");
  app.add_option(
         "--final-eval", o->final_eval,
         "the run folders' subfolder holding the final evaluation of the last checkpoint (its passive policy in "
         "NAME-passive/); deploy/campaign.sh writes final-eval (the run's own goals) and final-eval-selection "
         "(other goals, to choose variants on)")
      ->type_name("NAME")
      ->default_val("final-eval");
  app.add_option("--methods", o->methods,
                 "only these methods (as the run folders name them: srics,smorl,...), in figures and table; e.g. one "
                 "panel of the methods and one of the ablations")
      ->delimiter(',')
      ->type_name("LIST");
  app.add_option("--panel", o->panel, "names the files <env>-NAME-*.png (and the titles) so that panels share --out")
      ->type_name("NAME");
  app.add_option("--band", o->band, "the curves' band: std (mean ± 1 sample sd over seeds, as the paper) or minmax")
      ->transform(CLI::CheckedTransformer(std::map<std::string, analysis::CompareOptions::Band>{
          {"std", analysis::CompareOptions::Band::kStd}, {"minmax", analysis::CompareOptions::Band::kMinMax}}))
      ->default_str("std");
}

// ---- srics eval
void AddEvalOptions(CLI::App& app, eval::EvalArgs* a, bool* no_video) {
  app.description(
      "plays the run's evaluation protocol with the checkpoint's policy (the evaluating actors' code and seeds) and\n"
      "writes DIR/episodes.csv (per-episode distances, success, per-subgoal success) and a video of each episode\n"
      "(MuJoCo's renderer, headless EGL; goals as translucent markers). Exit codes: 0 done, 1 no or a corrupt\n"
      "checkpoint or graph, no renderer, ffmpeg failing; 2 bad arguments or config");
  app.add_option("RUN_DIR|CHECKPOINT", a->targets,
                 "a run folder (its checkpoint.srics, config.yaml and, for SRICS, graph.json) or a checkpoint file "
                 "(config.yaml and graph.json from its folder); several run folders with --cross-protocol or "
                 "--seen/--unseen")
      ->required();
  app.add_option("--episodes", a->episodes, "evaluation episodes (default: the config's actors.eval_episodes)")
      ->check(cli::Integer(1, 100000))
      ->default_str("");
  app.add_option("--out", a->out_dir, "default: <run folder>/eval")->type_name("DIR");
  app.add_option("--format", a->format,
                 "mp4 (ffmpeg), gif (ffmpeg) or png (frames; no ffmpeg needed); default mp4 when ffmpeg is installed "
                 "(deploy/install-deps.sh video), else png")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return env::ParseVideoFormat(text) ? "" : "expected mp4, gif or png, got '" + text + "'";
          },
          ""));
  app.add_flag("--no-video", *no_video, "write the metrics only");
  app.add_option("--config", a->config_file, "the run's config (default: config.yaml beside the checkpoint)")
      ->type_name("FILE");
  app.add_option("--graph", a->graph_file, "the run's graph (default: graph.json beside the checkpoint)")
      ->type_name("FILE");
  cli::AddSetOption(app, &a->overrides, "override a value of the run's config");
  app.add_option("--width", a->render.width, "frame width in pixels (even, 16 to 4096)")->check(cli::Integer(1, 4096));
  app.add_option("--height", a->render.height, "frame height in pixels (even, 16 to 4096)")
      ->check(cli::Integer(1, 4096));
  app.add_option("--fps", a->fps, "video frames per second (10: real time)")->check(cli::Integer(1, 240));
  app.add_option("--protocol", a->protocol,
                 "depth (the graph's subgoals in depth order, as SRICS evaluates; methods without a graph use the "
                 "table's graph by construction unless --graph) or random (every entity, random order, as SMORL); "
                 "default: the method's own")
      ->check(CLI::IsMember({"depth", "random"}));
  app.add_option("--goal-set", a->goal_set,
                 "the evaluation goals of a run with this seed (default: the run's own), to compare runs on the same "
                 "goals")
      ->check(cli::Integer(1, 1000000000))
      ->default_str("");
  app.add_flag("--cross-protocol", a->cross_protocol,
               "a study over the RUN_DIRs: each final policy under both protocols (depth, random) on the goals of "
               "each --goal-sets seed; writes OUT/cross-eval.csv and .md (episodes default 20)");
  app.add_option("--goal-sets", a->goal_sets, "with --cross-protocol: evaluation seeds whose goals are played")
      ->delimiter(',')
      ->check(cli::Integer(1, 1000000000))
      ->default_str("1,2,3");
  app.add_option("--seen", a->seen,
                 "a study over the RUN_DIRs: object combinations the runs trained on, catalogue ids (default "
                 "'1,2,3 1,2,4 1,3,4'); each final policy and the passive baseline play every combination and "
                 "--unseen's; writes OUT/seen-unseen.csv and .md (episodes default 50)");
  app.add_option("--unseen", a->unseen, "the held-out combination of the --seen study (default '2,3,4')");
  app.add_flag("--passive", a->passive,
               "play the passive baseline (the hand never moves) on the same goals instead of the checkpoint's "
               "policy (no checkpoint needed): the figure the run's eval.csv divides by");
}

void FinishEvalArgs(eval::EvalArgs* a, bool no_video) {
  a->video = !no_video;
  if (!a->targets.empty()) a->target = a->targets.front();
  if (a->targets.size() > 1 && !eval::IsEvalStudy(*a))
    throw std::invalid_argument("several RUN_DIRs are a study: add --cross-protocol or --seen and --unseen");
  try {
    env::CheckRenderOptions(a->render);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("--" + std::string(e.what()));
  }
}

// ---- srics learn-graph
void AddLearnGraphOptions(CLI::App& app, LearnGraphOptions* o) {
  app.description(
      "learns the interaction graph of an environment preset (or any run config) in process: actors explore at\n"
      "random, the graph service trains its GNN; DIR gets graph.json and its pictures. The last line compares the\n"
      "learned graph with the one by construction");
  CLI::Option* env = app.add_option("--env", o->env_file, "an environment preset or run config")
                         ->transform(cli::InstalledConfig())
                         ->type_name("FILE");
  CLI::Option* table = app.add_option_function<uint64_t>(
      "--random-table", [o](uint64_t seed) { o->table_seed = seed; },
      "a random table (objects, shapes, masses, static objects, ropes and springs drawn from seed N) instead of a "
      "file; written to DIR/env.yaml");
  table->check(cli::Integer(0))->type_name("N");
  env->excludes(table);
  app.add_option("--out", o->out_dir, "the folder for graph.json and its pictures")->type_name("DIR");
  // kept apart and appended after parsing: --set assigns its values to the whole list, which
  // dropped a seed pushed there before (every --seed gave seed 1's graph when --set was given)
  app.add_option("--seed", o->seed, "run.seed (the actors' and the graph service's random streams)")
      ->check(cli::Integer(0));
  cli::AddSetOption(app, &o->overrides, "override a config value");
  app.add_flag("--expected", o->expected_only, "print the graph the table implies by construction and exit");
  app.add_flag("--evidence", o->evidence_only,
               "collect the random-action data, print its tie evidence (onsets at a distance, by mover) and the "
               "graph by construction, and stop before training");
}

void FinishLearnGraphOptions(LearnGraphOptions* o) {
  if (o->env_file.empty() && !o->table_seed) throw std::invalid_argument("give one of --env FILE and --random-table N");
  if (o->out_dir.empty() && !o->expected_only) throw std::invalid_argument("--out is required");
  if (o->seed) o->overrides.push_back("run.seed=" + std::to_string(*o->seed));
}

// A subcommand alone, for the Parse*Args functions.
template <typename Add>
void ParseAlone(const std::string& name, const std::vector<std::string>& args, Add add) {
  CLI::App app{"", name};
  cli::Configure(app);
  add(app);
  cli::ParseOrThrow(app, args);
}

// A subcommand alone whose options keep text aside that is checked after parsing (run, sweep).
template <typename Options, typename Text>
Options ParseAloneWithText(const std::string& name, const std::vector<std::string>& args,
                           void (*add)(CLI::App&, Options*, Text*), void (*finish)(Options*, const Text&)) {
  Options o;
  Text text;
  ParseAlone(name, args, [&](CLI::App& app) { add(app, &o, &text); });
  finish(&o, text);
  return o;
}

// ---- srics column
void AddColumnOptions(CLI::App& app, analysis::ColumnOptions* o) {
  app.description(
      "the largest value of one column of a run folder's CSV file (eval.csv, learner.csv, nodes.csv, ...) over\n"
      "the rows that match every --where; 0 when none has a number there yet. For scripts that watch a run.\n"
      "Exit codes: 0 printed, 1 no such file or column");
  app.add_option("FILE", o->file, "a run folder's CSV file")->required();
  app.add_option("COLUMN", o->column, "the column, by its header name")->required();
  app.add_option("--where", o->where, "only rows whose NAME field is VALUE (repeatable; text equality)")
      ->type_name("NAME=VALUE");
}

}  // namespace

LaunchOptions ParseRunArgs(const std::vector<std::string>& args) {
  return ParseAloneWithText("srics run", args, AddRunOptions, FinishRunOptions);
}

SweepOptions ParseSweepArgs(const std::vector<std::string>& args) {
  return ParseAloneWithText("srics sweep", args, AddSweepOptions, FinishSweepOptions);
}

analysis::CompareOptions ParseCompareArgs(const std::vector<std::string>& args) {
  analysis::CompareOptions o;
  ParseAlone("srics compare", args, [&](CLI::App& app) { AddCompareOptions(app, &o); });
  return o;
}

eval::EvalArgs ParseEvalArgs(const std::vector<std::string>& args) {
  eval::EvalArgs a;
  bool no_video = false;
  ParseAlone("srics eval", args, [&](CLI::App& app) { AddEvalOptions(app, &a, &no_video); });
  FinishEvalArgs(&a, no_video);
  return a;
}

LearnGraphOptions ParseLearnGraphArgs(const std::vector<std::string>& args) {
  LearnGraphOptions o;
  ParseAlone("srics learn-graph", args, [&](CLI::App& app) { AddLearnGraphOptions(app, &o); });
  FinishLearnGraphOptions(&o);
  return o;
}

std::optional<int> ParseSricsCommandLine(int argc, char** argv, SricsCommand* command) {
  CLI::App app{
      "SRICS-DDS: distributed SRICS training runs, experiments over methods and seeds, trained policies "
      "watched. `srics SUBCOMMAND --help` for each one's options.",
      "srics"};
  cli::Configure(app);
  app.require_subcommand(1);
  using Kind = SricsCommand::Kind;
  struct Sub {
    CLI::App* app;
    Kind kind;
  };
  std::vector<Sub> subs;
  auto add = [&](const std::string& name, const std::string& summary, Kind kind) {
    CLI::App* sub = app.add_subcommand(name, summary);
    cli::Configure(*sub);
    subs.push_back({sub, kind});
    return sub;
  };
  RunText run_text;
  SweepText sweep_text;
  bool no_video = false;
  AddRunOptions(*add("run", "one training run on this machine (processes over DDS, or --in-process)", Kind::kRun),
                &command->run, &run_text);
  AddSweepOptions(*add("sweep", "a resumable grid of runs over methods and seeds", Kind::kSweep), &command->sweep,
                  &sweep_text);
  AddCompareOptions(*add("compare", "figures and tables over the runs of sweeps", Kind::kCompare), &command->compare);
  AddEvalOptions(*add("eval", "a trained policy's evaluation episodes: metrics and videos", Kind::kEval),
                 &command->eval, &no_video);
  AddLearnGraphOptions(*add("learn-graph", "learn an environment's interaction graph in process", Kind::kLearnGraph),
                       &command->learn_graph);
  AddColumnOptions(*add("column", "the largest value of a column of a run folder's CSV file", Kind::kColumn),
                   &command->column);
  if (const auto code = cli::Parse(app, argc, argv)) return code;
  for (const Sub& sub : subs)
    if (sub.app->parsed()) command->kind = sub.kind;
  command->name = cli::CommandName(app);
  try {
    switch (command->kind) {
      case Kind::kRun: FinishRunOptions(&command->run, run_text); break;
      case Kind::kSweep: FinishSweepOptions(&command->sweep, sweep_text); break;
      case Kind::kCompare: break;
      case Kind::kEval: FinishEvalArgs(&command->eval, no_video); break;
      case Kind::kLearnGraph: FinishLearnGraphOptions(&command->learn_graph); break;
      case Kind::kColumn: break;
    }
  } catch (const std::invalid_argument& e) {
    return cli::UsageError(command->name, e.what());
  }
  return std::nullopt;
}

}  // namespace srics::launcher
