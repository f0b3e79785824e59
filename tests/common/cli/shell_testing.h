#pragma once
// Running the project's programs from a test the way a user's shell does.

#include <sys/wait.h>

#include <cstdio>
#include <string>
#include <utility>

namespace srics::cli::testing {

// Runs a shell command with no input: the exit code (-1 when it did not exit) and its stdout
// and stderr together.
inline std::pair<int, std::string> Shell(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1 </dev/null").c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  std::string output;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace srics::cli::testing
