#include "common/files/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace srics::files {

namespace fs = std::filesystem;

int FileSystem::Open(const std::string& path, int flags, mode_t mode) { return ::open(path.c_str(), flags, mode); }
ssize_t FileSystem::Write(int fd, const void* data, size_t size) { return ::write(fd, data, size); }
int FileSystem::Fsync(int fd) { return ::fsync(fd); }
int FileSystem::Close(int fd) { return ::close(fd); }
int FileSystem::Rename(const std::string& from, const std::string& to) { return ::rename(from.c_str(), to.c_str()); }
int FileSystem::Link(const std::string& from, const std::string& to) { return ::link(from.c_str(), to.c_str()); }
int FileSystem::Unlink(const std::string& path) { return ::unlink(path.c_str()); }

FileSystem& FileSystem::Posix() {
  static FileSystem posix;
  return posix;
}

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
  if (this != &other) {
    Reset();
    fd_ = other.fd_;
    fs_ = other.fs_;
    other.fd_ = -1;
  }
  return *this;
}

int UniqueFd::Reset() {
  if (fd_ < 0) return 0;
  const int result = fs_->Close(fd_);
  fd_ = -1;
  return result;
}

namespace {

std::string Reason(int error_number) { return std::strerror(error_number); }

std::string FolderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

bool Exists(const std::string& path) {
  std::error_code ignored;
  return fs::exists(path, ignored);
}

// Writes and flushes `bytes` to `tmp`; on failure removes it and throws, naming `path` and
// what became of it.
void WriteTemporary(const std::string& path, const std::string& tmp, std::string_view bytes, FileSystem& fs) {
  const bool had_previous = Exists(path);
  auto fail = [&](const std::string& step, int error_number, UniqueFd* fd) {
    if (fd) fd->Reset();
    fs.Unlink(tmp);
    throw FileError("cannot write " + path + ": " + step + " " + tmp + " failed: " + Reason(error_number) + "; " +
                        (had_previous ? "the previous " + path + " is kept" : "there is no previous " + path) + ", " +
                        tmp + " removed",
                    error_number);
  };
  UniqueFd fd(fs.Open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644), &fs);
  if (!fd) fail("creating", errno, nullptr);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = fs.Write(fd.get(), bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error_number = n < 0 ? errno : ENOSPC;
      fail("writing " + std::to_string(bytes.size()) + " bytes (" + std::to_string(done) + " written) to", error_number,
           &fd);
    }
    done += static_cast<size_t>(n);
  }
  if (fs.Fsync(fd.get()) != 0) fail("flushing", errno, &fd);
  if (fd.Reset() != 0) fail("closing", errno, nullptr);
}

}  // namespace

void SyncDirectory(const std::string& dir, FileSystem& fs) {
  UniqueFd fd(fs.Open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC, 0), &fs);
  if (!fd) throw FileError("cannot open the folder " + dir + " to flush it: " + Reason(errno), errno);
  if (fs.Fsync(fd.get()) != 0) throw FileError("cannot flush the folder " + dir + ": " + Reason(errno), errno);
}

void WriteFileDurably(const std::string& path, std::string_view bytes, FileSystem& fs) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(path, tmp, bytes, fs);
  if (fs.Rename(tmp, path) != 0) {
    const int error_number = errno;
    fs.Unlink(tmp);
    throw FileError("cannot rename " + tmp + " to " + path + ": " + Reason(error_number) + "; " + tmp + " removed",
                    error_number);
  }
  SyncDirectory(FolderOf(path), fs);
}

std::vector<std::string> Generations(const std::string& path) {
  std::vector<std::pair<long, std::string>> found;
  if (Exists(path)) found.emplace_back(0, path);
  const fs::path p(path);
  const std::string prefix = p.filename().string() + ".";
  std::error_code error;
  for (fs::directory_iterator it(FolderOf(path), error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string number = name.substr(prefix.size());
    if (number.size() > 6 || !std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    const long k = std::stol(number);
    if (k >= 1) found.emplace_back(k, (p.parent_path() / name).string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> paths;
  for (auto& [k, name] : found) paths.push_back(std::move(name));
  return paths;
}

void WriteGeneration(const std::string& path, int keep, std::string_view bytes, FileSystem& fs) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(path, tmp, bytes, fs);
  auto generation = [&](int k) { return path + "." + std::to_string(k); };
  auto fail = [&](const std::string& what) {
    const int error_number = errno;
    throw FileError("cannot keep the generations of " + path + ": " + what + ": " + Reason(error_number), error_number);
  };
  if (keep > 1 && Exists(path)) {
    for (int k = keep - 1; k >= 2; --k)
      if (Exists(generation(k - 1)) && fs.Rename(generation(k - 1), generation(k)) != 0)
        fail("renaming " + generation(k - 1) + " to " + generation(k));
    if (fs.Unlink(generation(1)) != 0 && errno != ENOENT) fail("removing " + generation(1));
    // a second name for the current file: `path` stays until the new one replaces it
    if (fs.Link(path, generation(1)) != 0 && fs.Rename(path, generation(1)) != 0)
      fail("keeping " + path + " as " + generation(1));
  }
  if (fs.Rename(tmp, path) != 0) {
    const int error_number = errno;
    fs.Unlink(tmp);
    throw FileError("cannot rename " + tmp + " to " + path + ": " + Reason(error_number) + "; " + tmp + " removed",
                    error_number);
  }
  // generations beyond `keep` (left by a larger keep before) go
  if (keep >= 1)
    for (const std::string& old : Generations(path))
      if (old != path && std::stol(old.substr(path.size() + 1)) >= keep) fs.Unlink(old);
  SyncDirectory(FolderOf(path), fs);
}

std::string SetAside(const std::string& path, const std::string& suffix, FileSystem& fs) {
  std::string aside = path + suffix;
  for (int k = 2; Exists(aside); ++k) aside = path + suffix + "." + std::to_string(k);
  if (fs.Rename(path, aside) != 0)
    throw FileError("cannot set " + path + " aside as " + aside + ": " + Reason(errno), errno);
  SyncDirectory(FolderOf(path), fs);
  return aside;
}

}  // namespace srics::files
