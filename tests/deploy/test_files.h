// Reading back the files a deploy program wrote (logs, CSVs, stand-in outputs).
#ifndef SRICS_TESTS_DEPLOY_TEST_FILES_H_
#define SRICS_TESTS_DEPLOY_TEST_FILES_H_

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace srics::deploy::testing {

// The whole file, or "" when it cannot be read.
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace srics::deploy::testing

#endif  // SRICS_TESTS_DEPLOY_TEST_FILES_H_
