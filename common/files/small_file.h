#pragma once
// Reading the small text files the project writes and reads back (configs, resolved-config.yaml,
// sweep.yaml, outcome.yaml, best.yaml, graph.json), which may also come from someone else's
// folder: read whole, but never more than a limit, so that a file of gigabytes is refused at
// once, with its name and the limit, instead of filling the memory.
//
//   const std::string text = files::ReadSmallFile(dir + "/outcome.yaml");   // throws SmallFileError

#include <cstddef>
#include <stdexcept>
#include <string>

namespace srics::files {

// Every such file the project writes is a few kB; the largest (a graph.json of many entities,
// a config with a long actor list) stays far below.
inline constexpr size_t kSmallFileMaxBytes = size_t{1} << 20;

// A file that could not be opened or is over the limit; what() names the file and the reason.
class SmallFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The whole file; throws SmallFileError when it cannot be opened or holds more than max_bytes
// (judged before reading when its size is known, and while reading otherwise: a pipe, /dev/zero).
std::string ReadSmallFile(const std::string& path, size_t max_bytes = kSmallFileMaxBytes);

}  // namespace srics::files
