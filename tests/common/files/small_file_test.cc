// Issue 39: small files (configs, run-folder files, graph.json) are read under a size limit, so a
// file of gigabytes someone sent is refused at once, naming the file and the limit.
#include "common/files/small_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "tests/common/files/test_files.h"

namespace srics::files {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class SmallFileTest : public ::testing::Test {
 protected:
  files::testing::ScratchFolder dir_{"srics-small-file"};
};

TEST_F(SmallFileTest, ReadsAFileUpToTheLimitWhole) {
  const std::string path = (dir_ / "ok.yaml").string();
  const std::string text = "run:\n  name: x\n" + std::string(1000, '#') + "\n";
  std::ofstream(path) << text;
  EXPECT_EQ(ReadSmallFile(path), text);
  EXPECT_EQ(ReadSmallFile(path, text.size()), text);  // the limit itself is allowed
}

TEST_F(SmallFileTest, RefusesAFileOverTheLimitNamingFileSizeAndLimit) {
  const std::string path = (dir_ / "big.yaml").string();
  std::ofstream(path) << std::string(101, 'x');
  try {
    ReadSmallFile(path, 100);
    FAIL() << "accepted";
  } catch (const SmallFileError& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": 101 bytes, over the limit of 100 bytes for this file (it is not one "
                                         "this project wrote)");
  }
}

TEST_F(SmallFileTest, AnEndlessStreamIsCutAtTheLimitNotReadToTheEnd) {
  const auto start = std::chrono::steady_clock::now();
  try {
    ReadSmallFile("/dev/zero", 1 << 20);
    FAIL() << "accepted";
  } catch (const SmallFileError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/dev/zero: more than that, over the limit of 1048576 bytes"));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST_F(SmallFileTest, AMissingFileIsNamed) {
  EXPECT_THROW(
      {
        try {
          ReadSmallFile((dir_ / "absent.yaml").string());
        } catch (const SmallFileError& e) {
          EXPECT_THAT(e.what(), HasSubstr("absent.yaml: cannot open (No such file or directory)"));
          throw;
        }
      },
      SmallFileError);
}

}  // namespace
}  // namespace srics::files
