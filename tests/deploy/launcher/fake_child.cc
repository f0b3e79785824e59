// A stand-in child for the launcher tests. Prints "start <pid>" first, then behaves as told:
//
//   fake_child run                      runs until SIGINT/SIGTERM, then exits 0
//   fake_child crash-once MARKER HOW [MS]  first start (MARKER missing): creates MARKER and
//                                       dies (HOW: a number = exit code, "kill" = SIGKILL
//                                       itself); later starts: like run (or exit0-after MS)
//   fake_child fail CODE                exits with CODE at once
//   fake_child exit0-after MS           exits 0 after MS milliseconds (or 0 on SIGINT)
//   fake_child stubborn                 ignores SIGINT and SIGTERM, runs until SIGKILL
//
// Called under the name of a role program (srics-actor, srics-learner, srics-graph; the
// launcher test links these names to it), the mode comes from the environment variable
// FAKE_<ROLE> (FAKE_ACTOR, FAKE_LEARNER, FAKE_GRAPH), with ':' between words; an actor
// uses FAKE_ACTOR_<ID> first if set. Default: run.

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

volatile sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

void RunUntilSignal() {
  while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

std::vector<std::string> ModeFromRole(const std::string& name, int argc, char** argv) {
  std::string role = name.substr(std::string("srics-").size());
  for (char& c : role) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const char* mode = nullptr;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--id") mode = std::getenv(("FAKE_" + role + "_" + argv[i + 1]).c_str());
  if (!mode) mode = std::getenv(("FAKE_" + role).c_str());
  std::vector<std::string> words;
  std::stringstream in(mode ? mode : "run");
  for (std::string word; std::getline(in, word, ':');) words.push_back(word);
  return words;
}

}  // namespace

int main(int argc, char** argv) {
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::printf("start %d\n", static_cast<int>(getpid()));
  std::fflush(stdout);

  std::string name = argv[0];
  name = name.substr(name.rfind('/') + 1);
  std::vector<std::string> mode;
  if (name.rfind("srics-", 0) == 0) {
    mode = ModeFromRole(name, argc, argv);
  } else {
    for (int i = 1; i < argc; ++i) mode.push_back(argv[i]);
  }
  if (mode.empty()) return 64;

  if (mode[0] == "run") {
    RunUntilSignal();
    return 0;
  }
  if (mode[0] == "crash-once" && (mode.size() == 3 || mode.size() == 4)) {
    if (!std::ifstream(mode[1])) {
      std::ofstream(mode[1]) << "crashed\n";
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (mode[2] == "kill") raise(SIGKILL);
      return std::atoi(mode[2].c_str());
    }
    if (mode.size() == 3) {
      RunUntilSignal();
      return 0;
    }
    mode = {"exit0-after", mode[3]};
  }
  if (mode[0] == "fail" && mode.size() == 2) return std::atoi(mode[1].c_str());
  if (mode[0] == "exit0-after" && mode.size() == 2) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(std::atoi(mode[1].c_str()));
    while (!g_stop && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return 0;
  }
  if (mode[0] == "stubborn") {
    signal(SIGINT, SIG_IGN);
    signal(SIGTERM, SIG_IGN);
    for (;;) pause();
  }
  std::fprintf(stderr, "fake_child: unknown mode\n");
  return 64;
}
