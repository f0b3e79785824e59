#include "deploy/eval/eval_studies.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "common/config/config.h"
#include "deploy/analysis/eval_studies.h"

namespace srics::eval {
namespace {

namespace fs = std::filesystem;

// Every run folder has its final policy and config; with `subgoal_policies`, each run's method
// attempts subgoals (the protocols do not apply to SAC+HER's and HAC's full goal).
void CheckRunFolders(const std::vector<std::string>& runs, const std::vector<std::string>& overrides,
                     bool subgoal_policies) {
  for (const std::string& run : runs) {
    if (!fs::is_regular_file(fs::path(run) / "checkpoint.srics") || !fs::is_regular_file(fs::path(run) / "config.yaml"))
      throw std::invalid_argument(run + " has no checkpoint.srics and config.yaml");
    if (!subgoal_policies) continue;
    const config::Method method = config::LoadConfig((fs::path(run) / "config.yaml").string(), overrides).run.method;
    if (method == config::Method::kSacHer || method == config::Method::kHac)
      throw std::invalid_argument(run + ": " + config::MethodName(method) +
                                  " attempts the full goal; the protocols apply to subgoal policies");
  }
}

// While it lives, this process's stdout (fd 1) writes to `path`; restored when it goes.
class StdoutToFile {
 public:
  explicit StdoutToFile(const std::string& path) {
    std::cout.flush();
    std::fflush(stdout);
    saved_ = fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 0);  // not inherited by a child of Eval
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (saved_ < 0 || fd < 0 || dup2(fd, STDOUT_FILENO) < 0) {
      if (fd >= 0) close(fd);
      if (saved_ >= 0) close(saved_);
      throw std::runtime_error("cannot write " + path);
    }
    close(fd);
  }
  ~StdoutToFile() {
    std::cout.flush();
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
  }
  StdoutToFile(const StdoutToFile&) = delete;
  StdoutToFile& operator=(const StdoutToFile&) = delete;

 private:
  int saved_ = -1;
};

// One evaluation of a study: `one` on the run into `dir`, without video; its per-episode lines
// go to DIR.log (as `srics eval ... > DIR.log`), the progress line to stderr.
void PlayInto(EvalArgs one, const std::string& run, const fs::path& dir, int done, int total, const std::string& what) {
  std::cerr << "[" << done << "/" << total << "] " << fs::path(run).filename().string() << ", " << what << std::endl;
  one.target = run;
  one.targets = {run};
  one.out_dir = dir.string();
  one.video = false;
  one.cross_protocol = false;
  one.seen.clear();
  one.unseen.clear();
  fs::create_directories(dir.parent_path());
  StdoutToFile log(dir.string() + ".log");
  Eval(one);
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

std::string Joined(const std::vector<uint64_t>& values, const char* separator) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) text += (i ? separator : "") + std::to_string(values[i]);
  return text;
}

int CrossProtocol(const EvalArgs& args) {
  const fs::path out(args.out_dir);
  fs::create_directories(out / "raw");
  const std::vector<uint64_t> goal_sets = args.goal_sets.empty() ? std::vector<uint64_t>{1, 2, 3} : args.goal_sets;
  EvalArgs base = args;
  if (base.episodes <= 0) base.episodes = 20;
  std::string csv = std::string(analysis::kCrossEvalHeader) + "\n";
  const int total = static_cast<int>(args.targets.size() * 2 * goal_sets.size());
  int done = 0;
  for (const std::string& run : args.targets) {
    const std::string name = fs::path(run).filename().string();
    const std::string method =
        config::MethodName(config::LoadConfig((fs::path(run) / "config.yaml").string(), args.overrides).run.method);
    for (const char* protocol : {"depth", "random"})
      for (uint64_t goal_set : goal_sets) {
        const fs::path dir = out / "raw" / (name + "-" + protocol + "-goals" + std::to_string(goal_set));
        EvalArgs one = base;
        one.protocol = protocol;
        one.goal_set = goal_set;
        PlayInto(one, run, dir, ++done, total,
                 std::string("protocol ") + protocol + ", goals of seed " + std::to_string(goal_set));
        // the objects that have a subgoal: those the depth protocol attempted (a static one has none)
        const std::set<int> objects =
            analysis::AttemptedObjects(out / "raw" / (name + "-depth-goals" + std::to_string(goal_set)));
        csv += analysis::CrossEvalRow(name, method, protocol, goal_set, dir, objects) + "\n";
      }
  }
  WriteText(out / "cross-eval.csv", csv);
  const std::string table = analysis::CrossEvalTable(csv, Joined(goal_sets, " "), base.episodes);
  WriteText(out / "cross-eval.md", table);
  std::cout << table << std::flush;
  std::cerr << "wrote " << (out / "cross-eval.csv").string() << " and " << (out / "cross-eval.md").string()
            << std::endl;
  return 0;
}

std::vector<std::string> Words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// Refuses a combination that is not catalogue ids (from 1) joined by commas.
void CheckCombination(const std::string& combination, const char* flag) {
  bool digit = false;
  for (size_t i = 0; i < combination.size(); ++i) {
    const char c = combination[i];
    if (c >= '0' && c <= '9') {
      if (!digit && c == '0')
        throw std::invalid_argument(std::string(flag) + ": catalogue ids start at 1, got '" + combination + "'");
      digit = true;
    } else if (c == ',' && digit && i + 1 < combination.size()) {
      digit = false;
    } else {
      throw std::invalid_argument(
          std::string(flag) + ": a combination is catalogue ids joined by commas (1,2,3), got '" + combination + "'");
    }
  }
  if (!digit) throw std::invalid_argument(std::string(flag) + ": empty combination");
}

int SeenUnseen(const EvalArgs& args) {
  const fs::path out(args.out_dir);
  const std::vector<std::string> seen = Words(args.seen);
  fs::create_directories(out / "raw");
  EvalArgs base = args;
  if (base.episodes <= 0) base.episodes = 50;
  std::vector<std::string> combinations = seen;
  combinations.push_back(args.unseen);
  std::string csv = std::string(analysis::kSeenUnseenHeader) + "\n";
  const int total = static_cast<int>(args.targets.size() * combinations.size());
  int done = 0;
  for (const std::string& run : args.targets) {
    const std::string name = fs::path(run).filename().string();
    for (const std::string& c : combinations) {
      const std::string kind = c == args.unseen ? "unseen" : "seen";
      std::string tag = name + "-objects" + c, spaced = c;
      for (char& ch : tag) ch = ch == ',' ? '-' : ch;
      for (char& ch : spaced) ch = ch == ',' ? ' ' : ch;
      ++done;
      for (const bool passive : {false, true}) {
        EvalArgs one = base;
        one.passive = passive;
        one.overrides.push_back("env.eval_object_sets=[{present: [" + c + "]}]");
        PlayInto(one, run, out / "raw" / (tag + (passive ? "-passive" : "-policy")), done, total,
                 "objects " + c + " (" + kind + ")" + (passive ? ", passive" : ""));
      }
      csv += analysis::SeenUnseenRow(name, spaced, kind, out / "raw" / (tag + "-policy") / "episodes.csv",
                                     out / "raw" / (tag + "-passive") / "episodes.csv") +
             "\n";
    }
  }
  WriteText(out / "seen-unseen.csv", csv);
  const std::string table = analysis::SeenUnseenTable(csv, args.seen, args.unseen, base.episodes);
  WriteText(out / "seen-unseen.md", table);
  std::cout << table << std::flush;
  std::cerr << "wrote " << (out / "seen-unseen.csv").string() << " and " << (out / "seen-unseen.md").string()
            << std::endl;
  return 0;
}

}  // namespace

bool IsEvalStudy(const EvalArgs& args) { return args.cross_protocol || !args.seen.empty() || !args.unseen.empty(); }

int RunEvalStudy(const EvalArgs& args) {
  if (args.out_dir.empty())
    throw std::invalid_argument("--out DIR is required for --cross-protocol and --seen/--unseen");
  if (args.cross_protocol && (!args.seen.empty() || !args.unseen.empty()))
    throw std::invalid_argument("--cross-protocol and --seen/--unseen are two studies: one at a time");
  if (args.cross_protocol) {
    CheckRunFolders(args.targets, args.overrides, /*subgoal_policies=*/true);
    return CrossProtocol(args);
  }
  // the combinations of deploy/configs/env/rearrange-4-unseen.yaml unless given
  EvalArgs study = args;
  if (study.seen.empty()) study.seen = "1,2,3 1,2,4 1,3,4";
  if (study.unseen.empty()) study.unseen = "2,3,4";
  if (Words(study.unseen).size() != 1)
    throw std::invalid_argument("--unseen: one combination, got '" + study.unseen + "'");
  for (const std::string& c : Words(study.seen)) CheckCombination(c, "--seen");
  CheckCombination(study.unseen, "--unseen");
  CheckRunFolders(study.targets, study.overrides, /*subgoal_policies=*/false);
  return SeenUnseen(study);
}

}  // namespace srics::eval
