// srics: the launcher. `srics run CONFIG ...` runs a whole training run on this machine
// (launcher.h); `srics sweep` a grid of runs over methods and seeds (sweep.h); `srics compare`
// draws figures and tables from sweeps (deploy/analysis/compare.h); `srics eval` plays a trained policy's
// evaluation episodes into metrics and videos (eval.h); `srics learn-graph` learns an
// environment's graph (in_process_run.h); `srics column` the largest value of a run folder's CSV
// column (deploy/analysis/column.h). Options: command_line.h, `srics SUBCOMMAND --help`.

#include <iostream>
#include <stdexcept>

#include "common/config/config_error.h"
#include "common/process/memory.h"
#include "common/transport/shutdown.h"
#include "deploy/eval/eval_studies.h"
#include "deploy/launcher/command_line.h"

namespace {

namespace launcher = srics::launcher;

int RunCommand(const launcher::SricsCommand& command) {
  using Kind = launcher::SricsCommand::Kind;
  switch (command.kind) {
    case Kind::kRun: return launcher::Run(command.run);
    case Kind::kSweep: return launcher::Sweep(command.sweep);
    case Kind::kCompare: return srics::analysis::Compare(command.compare);
    case Kind::kEval:
      return srics::eval::IsEvalStudy(command.eval) ? srics::eval::RunEvalStudy(command.eval)
                                                    : srics::eval::Eval(command.eval);
    case Kind::kLearnGraph: return launcher::LearnGraph(command.learn_graph);
    case Kind::kColumn: return srics::analysis::Column(command.column);
  }
  return srics::kExitFailed;
}

}  // namespace

int main(int argc, char** argv) {
  srics::process::SetUpHeap();  // the in-process runs hold a learner
  srics::transport::Shutdown::InstallSignalHandlers();
  launcher::SricsCommand command;
  if (const auto code = launcher::ParseSricsCommandLine(argc, argv, &command)) return *code;
  try {
    return RunCommand(command);
  } catch (const srics::config::ConfigError& e) {  // names the file, line and key
    std::cerr << command.name << ": " << e.what() << "\n";
    return srics::kExitUsage;
  } catch (const std::invalid_argument& e) {  // an argument that does not fit the files it names
    std::cerr << command.name << ": " << e.what() << "\n";
    return srics::kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << command.name << ": " << e.what() << "\n";
    return srics::kExitFailed;
  }
}
