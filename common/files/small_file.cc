#include "common/files/small_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace srics::files {

namespace {

[[noreturn]] void TooLarge(const std::string& path, const std::string& size, size_t max_bytes) {
  throw SmallFileError(path + ": " + size + ", over the limit of " + std::to_string(max_bytes) +
                       " bytes for this file (it is not one this project wrote)");
}

}  // namespace

std::string ReadSmallFile(const std::string& path, size_t max_bytes) {
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) {
    const auto size = std::filesystem::file_size(path, error);
    if (!error && size > max_bytes) TooLarge(path, std::to_string(size) + " bytes", max_bytes);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SmallFileError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::string text;
  char buffer[16384];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<size_t>(in.gcount()));
    if (text.size() > max_bytes) TooLarge(path, "more than that", max_bytes);
  }
  return text;
}

}  // namespace srics::files
