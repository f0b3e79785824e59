// The installed programs (cmake --install into a scratch prefix) find their configs relative
// to their own folder: from any working folder, `srics learn-graph --expected --env NAME` reads
// <prefix>/share/srics-dds/configs/NAME, and an unknown name is reported as given.

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/common/cli/shell_testing.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using srics::cli::testing::Shell;

TEST(InstalledConfigTest, InstalledProgramsFindTheirConfigsFromAnyFolder) {
  const fs::path prefix = fs::temp_directory_path() / ("srics_install_test_" + std::to_string(getpid()));
  const fs::path elsewhere = prefix / "elsewhere";
  fs::remove_all(prefix);
  fs::create_directories(elsewhere);
  auto [code, output] =
      Shell("cmake --install '" + std::string(SRICS_BINARY_DIR) + "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(code, 0) << output;
  ASSERT_TRUE(fs::exists(prefix / "share/srics-dds/configs/default.yaml"));
  const std::string srics = (prefix / "bin/srics").string();

  std::tie(code, output) =
      Shell("cd '" + elsewhere.string() + "' && '" + srics + "' learn-graph --expected --env env/relational-4.yaml");
  EXPECT_EQ(code, 0) << output;
  EXPECT_THAT(output, HasSubstr("action->0, 0->2, 0->3, 0->4, 2->3, 3->2"));
  // the name as the checkout's READMEs write it
  std::tie(code, output) = Shell("cd '" + elsewhere.string() + "' && '" + srics +
                                 "' learn-graph --expected --env deploy/configs/env/relational-4.yaml");
  EXPECT_EQ(code, 0) << output;
  // a file where the user is wins over the installed one
  fs::create_directories(elsewhere / "env");
  fs::copy_file(prefix / "share/srics-dds/configs/env/rearrange-1.yaml", elsewhere / "env/relational-4.yaml");
  std::tie(code, output) =
      Shell("cd '" + elsewhere.string() + "' && '" + srics + "' learn-graph --expected --env env/relational-4.yaml");
  EXPECT_EQ(code, 0) << output;
  EXPECT_THAT(output, HasSubstr("action->0"));
  EXPECT_THAT(output, ::testing::Not(HasSubstr("0->2"))) << "the local file, one object";
  // no such config anywhere: named as given, exit 2
  std::tie(code, output) = Shell("cd '" + elsewhere.string() + "' && '" + srics + "' run nowhere.yaml");
  EXPECT_EQ(code, 2) << output;
  EXPECT_THAT(output, HasSubstr("nowhere.yaml"));
  fs::remove_all(prefix);
}

}  // namespace
