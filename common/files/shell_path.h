#pragma once
// A path as one word of a `sh -c` command line (popen, std::system): single-quoted, with each
// single quote inside written as '\'' , so any folder name a user picks (spaces, quotes, $) is
// passed through unchanged.
//
//   popen(("gnuplot " + files::ShellQuote(script)).c_str(), "r");

#include <string>

namespace srics::files {

inline std::string ShellQuote(const std::string& word) {
  std::string quoted = "'";
  for (const char c : word) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

}  // namespace srics::files
