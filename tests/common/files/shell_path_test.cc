// files::ShellQuote: a path survives `sh -c` unchanged, whatever its characters.

#include "common/files/shell_path.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace srics::files {
namespace {

std::string EchoThroughShell(const std::string& word) {
  FILE* pipe = ::popen(("printf '%s' " + ShellQuote(word)).c_str(), "r");
  std::string out;
  char buffer[256];
  while (size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  ::pclose(pipe);
  return out;
}

TEST(ShellQuoteTest, QuotesByHand) {
  EXPECT_EQ(ShellQuote("plain"), "'plain'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
}

TEST(ShellQuoteTest, EveryAwkwardPathReachesTheCommandUnchanged) {
  for (const std::string path : {"/tmp/it's out/a.png", "a b", "$HOME", "x;rm -rf y", "'", "''", "a\"b`c`", "\\"})
    EXPECT_EQ(EchoThroughShell(path), path);
}

}  // namespace
}  // namespace srics::files
