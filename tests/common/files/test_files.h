#pragma once
// Files in tests: reading back what the code under test wrote (logs, CSVs, checkpoints,
// pictures, stand-in outputs) and scratch folders for it to write into.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

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

// A fresh, empty folder for one test, <temp>/<name>_<test name>_<pid>, removed with the object:
// as a fixture's member, no test sees another's files and none is left behind.
class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& name) : path_(FreshFolder(name + "_" + TestName())) {}
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& child) const { return path_ / child; }
  std::string string() const { return path_.string(); }

 private:
  // The running test's name ("" outside a test): fixtures of one process get folders of their own.
  static std::string TestName() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    return test != nullptr ? test->name() : "";
  }

  std::filesystem::path path_;
};

}  // namespace srics::files::testing
