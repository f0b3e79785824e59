#pragma once
// What the config tests share: a fresh folder of YAML files for each test.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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

}  // namespace srics::config::testing
