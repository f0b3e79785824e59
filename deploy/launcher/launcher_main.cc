// srics: the launcher. `srics run CONFIG ...` runs a whole training run on this machine (see
// launcher.h and `srics run --help`); `srics sweep` a grid of runs over methods and seeds
// (sweep.h); `srics compare` draws figures and tables from sweeps (compare.h); `srics eval`
// plays a trained policy's evaluation episodes into metrics and videos (eval.h); `srics
// learn-graph` learns an environment's graph.

#include <iostream>
#include <string>
#include <vector>

#include "common/config/config_error.h"
#include "common/transport/shutdown.h"
#include "deploy/launcher/compare.h"
#include "deploy/launcher/eval.h"
#include "deploy/launcher/in_process_run.h"
#include "deploy/launcher/launcher.h"
#include "deploy/launcher/sweep.h"

int main(int argc, char** argv) {
  namespace launcher = srics::launcher;
  srics::transport::Shutdown::InstallSignalHandlers();
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" ||
      (args[0] == "run" && args.size() > 1 && (args[1] == "-h" || args[1] == "--help"))) {
    std::cout << "srics run | sweep | compare | eval | learn-graph (each with --help)\n" << launcher::kRunUsage;
    return args.empty() ? launcher::kExitUsage : 0;
  }
  if (args[0] == "learn-graph") {
    try {
      return launcher::LearnGraph({args.begin() + 1, args.end()});
    } catch (const srics::config::ConfigError& e) {
      std::cerr << "srics learn-graph: " << e.what() << "\n";
      return launcher::kExitUsage;
    } catch (const std::invalid_argument& e) {
      std::cerr << "srics learn-graph: " << e.what() << "\n" << launcher::kLearnGraphUsage;
      return launcher::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "srics learn-graph: " << e.what() << "\n";
      return launcher::kExitFailed;
    }
  }
  if (args[0] == "sweep") {
    if (args.size() > 1 && (args[1] == "-h" || args[1] == "--help")) {
      std::cout << launcher::kSweepUsage;
      return 0;
    }
    try {
      return launcher::Sweep(launcher::ParseSweepArgs({args.begin() + 1, args.end()}));
    } catch (const srics::config::ConfigError& e) {
      std::cerr << "srics sweep: " << e.what() << "\n";
      return launcher::kExitUsage;
    } catch (const std::invalid_argument& e) {
      std::cerr << "srics sweep: " << e.what() << "\n" << launcher::kSweepUsage;
      return launcher::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "srics sweep: " << e.what() << "\n";
      return launcher::kExitFailed;
    }
  }
  if (args[0] == "compare") {
    if (args.size() > 1 && (args[1] == "-h" || args[1] == "--help")) {
      std::cout << launcher::kCompareUsage;
      return 0;
    }
    try {
      return launcher::Compare(launcher::ParseCompareArgs({args.begin() + 1, args.end()}));
    } catch (const std::invalid_argument& e) {
      std::cerr << "srics compare: " << e.what() << "\n" << launcher::kCompareUsage;
      return launcher::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "srics compare: " << e.what() << "\n";
      return launcher::kExitFailed;
    }
  }
  if (args[0] == "eval") {
    if (args.size() > 1 && (args[1] == "-h" || args[1] == "--help")) {
      std::cout << launcher::kEvalUsage;
      return 0;
    }
    try {
      return launcher::Eval(launcher::ParseEvalArgs({args.begin() + 1, args.end()}));
    } catch (const srics::config::ConfigError& e) {
      std::cerr << "srics eval: " << e.what() << "\n";
      return launcher::kExitUsage;
    } catch (const std::invalid_argument& e) {
      std::cerr << "srics eval: " << e.what() << "\n" << launcher::kEvalUsage;
      return launcher::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "srics eval: " << e.what() << "\n";
      return launcher::kExitFailed;
    }
  }
  if (args[0] != "run") {
    std::cerr << "srics: unknown command '" << args[0] << "'\n" << launcher::kRunUsage;
    return launcher::kExitUsage;
  }
  launcher::LaunchOptions options;
  try {
    options = launcher::ParseRunArgs({args.begin() + 1, args.end()});
  } catch (const std::exception& e) {
    std::cerr << "srics run: " << e.what() << "\n" << launcher::kRunUsage;
    return launcher::kExitUsage;
  }
  try {
    return launcher::Run(options);
  } catch (const srics::config::ConfigError& e) {
    std::cerr << "srics run: " << e.what() << "\n";
    return launcher::kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "srics run: " << e.what() << "\n";
    return launcher::kExitFailed;
  }
}
