#pragma once
// Files in tests: reading back what the code under test wrote (logs, CSVs, checkpoints,
// pictures, stand-in outputs) and a scratch folder for it to write into.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace srics::files::testing {

// The whole file, byte for byte, or "" when it cannot be read.
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A fresh, empty folder of this test process: <temp>/<name>_<pid>, emptied if it was there.
inline std::filesystem::path FreshFolder(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace srics::files::testing
