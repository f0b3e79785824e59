#pragma once
// What the config tests share: a fresh folder of YAML files for each test.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "tests/common/files/test_files.h"

namespace srics::config::testing {

// A fresh folder of YAML files for one test, removed afterwards.
class ConfigFiles : public ::testing::Test {
 protected:
  // Writes `text` to `name` in the folder (making its subfolders) and returns the file's path.
  std::string Write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }

  files::testing::ScratchFolder dir_{"srics-config-test"};
};

// `record` (a resolved-config.yaml's text) without the section keys `keys`, as a record written
// before they were always recorded reads. A key that is not there fails the test.
inline std::string WithoutRecordedKeys(std::string record, std::initializer_list<const char*> keys) {
  for (const std::string key : keys) {
    const size_t at = record.find("  " + key + ": ");
    if (at == std::string::npos) {
      ADD_FAILURE() << key << " is not in the record:\n" << record;
      continue;
    }
    record.erase(at, record.find('\n', at) + 1 - at);
  }
  return record;
}

}  // namespace srics::config::testing
