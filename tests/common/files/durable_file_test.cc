// Durable files (issue 15): what is renamed into place was flushed first and the folder
// after; a failed write (a full disk: injected, and a real tiny tmpfs where the test may
// mount one) keeps the previous file and removes its temporary file; generations keep the
// last K; a corrupt file is set aside under another name.

#include "common/files/durable_file.h"

#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "tests/common/files/test_files.h"

namespace srics::files {
namespace {

namespace fs = std::filesystem;

using testing::ReadFile;

class DurableFileTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  files::testing::ScratchFolder dir_{"srics-files-test"};
};

// Records the calls in order and fails the chosen one (after `fail_after` successful ones).
class ScriptedFileSystem : public FileSystem {
 public:
  std::vector<std::string> calls;
  std::string fail_call;  // "write", "fsync", "rename", ...
  int fail_errno = ENOSPC;
  int fail_after = 0;

  int Open(const std::string& path, int flags, mode_t mode) override {
    const bool dir = flags & O_DIRECTORY;
    Log(dir ? "open-dir " + fs::path(path).filename().string() : "open " + fs::path(path).filename().string());
    if (Fails("open")) return -1;
    const int fd = FileSystem::Open(path, flags, mode);
    if (dir) dir_fds_.push_back(fd);
    return fd;
  }
  ssize_t Write(int fd, const void* data, size_t size) override {
    Log("write");
    if (Fails("write")) return -1;
    // a full disk typically takes part of the data first
    return FileSystem::Write(fd, data, fail_call == "write" ? std::min<size_t>(size, 3) : size);
  }
  int Fsync(int fd) override {
    Log(std::find(dir_fds_.begin(), dir_fds_.end(), fd) != dir_fds_.end() ? "fsync-dir" : "fsync");
    if (Fails("fsync")) return -1;
    return FileSystem::Fsync(fd);
  }
  int Rename(const std::string& from, const std::string& to) override {
    Log("rename " + fs::path(from).filename().string() + " " + fs::path(to).filename().string());
    if (Fails("rename")) return -1;
    return FileSystem::Rename(from, to);
  }

 private:
  void Log(const std::string& call) { calls.push_back(call); }
  bool Fails(const std::string& kind) {
    if (kind != fail_call) return false;
    if (fail_after-- > 0) return false;
    errno = fail_errno;
    return true;
  }
  std::vector<int> dir_fds_;
};

TEST_F(DurableFileTest, TheFileIsFlushedBeforeTheRenameAndTheFolderAfter) {
  ScriptedFileSystem scripted;
  WriteFileDurably(Path("graph.json"), "{\"v\": 1}", scripted);
  EXPECT_EQ(ReadFile(Path("graph.json")), "{\"v\": 1}");
  EXPECT_FALSE(fs::exists(Path("graph.json.tmp")));
  const std::vector<std::string> expected = {"open graph.json.tmp",
                                             "write",
                                             "fsync",
                                             "rename graph.json.tmp graph.json",
                                             "open-dir " + dir_.path().filename().string(),
                                             "fsync-dir"};
  EXPECT_EQ(scripted.calls, expected);
}

TEST_F(DurableFileTest, AFullDiskKeepsThePreviousFileRemovesTheTemporaryOneAndSaysSo) {
  WriteFileDurably(Path("checkpoint.srics"), "old content");
  for (const char* call : {"write", "fsync"}) {
    ScriptedFileSystem full;
    full.fail_call = call;
    full.fail_errno = call == std::string("write") ? ENOSPC : EIO;
    try {
      WriteFileDurably(Path("checkpoint.srics"), std::string(1000, 'n'), full);
      ADD_FAILURE() << call << ": no error";
    } catch (const FileError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.error_number(), full.fail_errno);
      EXPECT_NE(message.find("cannot write " + Path("checkpoint.srics")), std::string::npos) << message;
      EXPECT_NE(message.find(std::strerror(full.fail_errno)), std::string::npos) << message;
      EXPECT_NE(message.find("the previous " + Path("checkpoint.srics") + " is kept"), std::string::npos) << message;
      EXPECT_NE(message.find(Path("checkpoint.srics.tmp") + " removed"), std::string::npos) << message;
    }
    EXPECT_EQ(ReadFile(Path("checkpoint.srics")), "old content") << call;
    EXPECT_FALSE(fs::exists(Path("checkpoint.srics.tmp"))) << call;
  }
}

TEST_F(DurableFileTest, GenerationsKeepTheLastKNewestFirst) {
  const std::string path = Path("checkpoint.srics");
  for (int g = 1; g <= 5; ++g) WriteGeneration(path, 3, "generation " + std::to_string(g));
  const std::vector<std::string> expected = {path, path + ".1", path + ".2"};
  EXPECT_EQ(Generations(path), expected);
  EXPECT_EQ(ReadFile(path), "generation 5");
  EXPECT_EQ(ReadFile(path + ".1"), "generation 4");
  EXPECT_EQ(ReadFile(path + ".2"), "generation 3");
  EXPECT_FALSE(fs::exists(path + ".3"));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  // fewer kept from now on: the older ones go
  WriteGeneration(path, 2, "generation 6");
  EXPECT_EQ(Generations(path), (std::vector<std::string>{path, path + ".1"}));
  EXPECT_EQ(ReadFile(path + ".1"), "generation 5");
  WriteGeneration(path, 1, "generation 7");
  EXPECT_EQ(Generations(path), std::vector<std::string>{path});
  EXPECT_EQ(ReadFile(path), "generation 7");
}

TEST_F(DurableFileTest, AFailedGenerationChangesNoGeneration) {
  const std::string path = Path("checkpoint.srics");
  for (int g = 1; g <= 3; ++g) WriteGeneration(path, 3, "generation " + std::to_string(g));
  ScriptedFileSystem full;
  full.fail_call = "write";
  EXPECT_THROW(WriteGeneration(path, 3, std::string(100, 'x'), full), FileError);
  EXPECT_EQ(Generations(path), (std::vector<std::string>{path, path + ".1", path + ".2"}));
  EXPECT_EQ(ReadFile(path), "generation 3");
  EXPECT_EQ(ReadFile(path + ".1"), "generation 2");
  EXPECT_EQ(ReadFile(path + ".2"), "generation 1");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST_F(DurableFileTest, SetAsideRenamesWithoutOverwriting) {
  const std::string path = Path("checkpoint.srics");
  WriteFileDurably(path, "bad 1");
  EXPECT_EQ(SetAside(path, ".corrupt"), path + ".corrupt");
  WriteFileDurably(path, "bad 2");
  EXPECT_EQ(SetAside(path, ".corrupt"), path + ".corrupt.2");
  EXPECT_EQ(ReadFile(path + ".corrupt"), "bad 1");
  EXPECT_EQ(ReadFile(path + ".corrupt.2"), "bad 2");
  EXPECT_TRUE(Generations(path).empty()) << "set-aside files are no generations";
}

// A real full disk: a 64 kB tmpfs in a mount namespace of a child process (root or user
// namespaces needed; skipped otherwise).
TEST_F(DurableFileTest, ARealFullDiskKeepsThePreviousCheckpoint) {
  const std::string mount_point = Path("tiny");
  fs::create_directories(mount_point);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (unshare(CLONE_NEWNS) != 0 && unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) _exit(77);
    if (mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) _exit(77);
    if (mount("tmpfs", mount_point.c_str(), "tmpfs", 0, "size=64k") != 0) _exit(77);
    const std::string path = mount_point + "/checkpoint.srics";
    const std::string first(40 * 1024, 'a'), second(40 * 1024, 'b');
    WriteGeneration(path, 3, first);
    try {
      WriteGeneration(path, 3, second);  // 80 kB do not fit in 64 kB
      _exit(1);
    } catch (const FileError& e) {
      if (e.error_number() != ENOSPC) _exit(2);
      if (std::string(e.what()).find("is kept") == std::string::npos) _exit(3);
    }
    if (ReadFile(path) != first) _exit(4);
    if (fs::exists(path + ".tmp")) _exit(5);
    if (Generations(path).size() != 1) _exit(6);
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "cannot mount a tmpfs here";
  EXPECT_EQ(WEXITSTATUS(status), 0)
      << "1 no error, 2 not ENOSPC, 3 message, 4 previous changed, 5 .tmp left, 6 generations";
}

}  // namespace
}  // namespace srics::files
