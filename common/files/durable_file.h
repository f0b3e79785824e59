#pragma once
// Files that survive a crash or a full disk: written to a temporary file, flushed to the disk
// (fsync), renamed into place and the folder flushed, so that after a power cut the name holds
// either the old or the new content, whole. A write that fails (ENOSPC, EIO, ...) removes its
// temporary file, leaves the previous file as it was and says so in the exception.
//
// Generations: a file kept with its predecessors (checkpoints): `path` is the newest,
// `path.1` the one before, ... up to `keep` files in all.
//
//   files::WriteFileDurably(dir + "/graph.json", text);
//   files::WriteGeneration(dir + "/checkpoint.srics", 3, bytes);   // the last 3 kept
//   for (const std::string& p : files::Generations(dir + "/checkpoint.srics")) ...  // newest first
//
// Every system call goes through a FileSystem, so tests inject failures (a full disk).

#include <sys/types.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace srics::files {

// A file operation that failed; what() names the file, the operation, the system's reason
// and what became of the previous file and the temporary one.
class FileError : public std::runtime_error {
 public:
  FileError(const std::string& what, int error_number) : std::runtime_error(what), errno_(error_number) {}
  int error_number() const { return errno_; }

 private:
  int errno_;
};

// The system calls of a durable write (POSIX semantics: -1 and errno on failure).
class FileSystem {
 public:
  virtual ~FileSystem() = default;
  virtual int Open(const std::string& path, int flags, mode_t mode);
  virtual ssize_t Write(int fd, const void* data, size_t size);
  virtual int Fsync(int fd);
  virtual int Close(int fd);
  virtual int Rename(const std::string& from, const std::string& to);
  virtual int Link(const std::string& from, const std::string& to);
  virtual int Unlink(const std::string& path);
  // The process's file system (these calls, unchanged).
  static FileSystem& Posix();
};

// An open file descriptor, closed when it goes (RAII).
class UniqueFd {
 public:
  UniqueFd() = default;
  UniqueFd(int fd, FileSystem* fs) : fd_(fd), fs_(fs) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.fd_), fs_(other.fs_) { other.fd_ = -1; }
  UniqueFd& operator=(UniqueFd&& other) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { Reset(); }
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  // Closes now; returns close()'s result (0 when there was nothing to close).
  int Reset();

 private:
  int fd_ = -1;
  FileSystem* fs_ = nullptr;
};

// Writes `bytes` to path + ".tmp", fsyncs it, renames it to `path` and fsyncs the folder.
// Throws FileError; the previous `path` is then unchanged and the temporary file removed.
void WriteFileDurably(const std::string& path, std::string_view bytes, FileSystem& fs = FileSystem::Posix());

// Flushes a folder's entries (after a rename into it). Throws FileError.
void SyncDirectory(const std::string& dir, FileSystem& fs = FileSystem::Posix());

// The generation files of `path` that exist, newest first: path, path.1, path.2, ...
// (every path.N in the folder, whatever keep was when they were written).
std::vector<std::string> Generations(const std::string& path);

// Writes `bytes` as the newest generation of `path`, keeping `keep` (>= 1) generations: the
// new file is written and flushed to path + ".tmp" first; then path.(keep-2) ... path.1 move
// one up (the oldest beyond `keep` is dropped), the current `path` becomes path.1 (a second
// name for it, so that `path` never goes missing) and the new file is renamed to `path`.
// Throws FileError; when writing the new file fails, every generation is unchanged.
void WriteGeneration(const std::string& path, int keep, std::string_view bytes, FileSystem& fs = FileSystem::Posix());

// Renames `path` to path + suffix (".corrupt"; path + suffix + ".2", ... when that exists)
// and returns the new name. Throws FileError.
std::string SetAside(const std::string& path, const std::string& suffix, FileSystem& fs = FileSystem::Posix());

}  // namespace srics::files
