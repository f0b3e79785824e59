#include "actor/env/render/video_writer.h"

#include <fcntl.h>
#include <png.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

extern char** environ;

namespace srics::env {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// Blocks SIGPIPE on this thread while frames go into the pipe, so that an ffmpeg that died is
// an EPIPE error here and not the end of the program; a SIGPIPE the write raised is taken
// back before the mask is restored.
class SigpipeBlock {
 public:
  SigpipeBlock() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGPIPE);
    sigset_t pending;
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
    pthread_sigmask(SIG_BLOCK, &set_, &old_);
  }
  ~SigpipeBlock() {
    if (broken_ && !was_pending_) {
      const timespec zero{};
      sigtimedwait(&set_, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlock(const SigpipeBlock&) = delete;
  SigpipeBlock& operator=(const SigpipeBlock&) = delete;
  void set_broken() { broken_ = true; }

 private:
  sigset_t set_, old_;
  bool was_pending_ = false;
  bool broken_ = false;
};

// posix_spawn's file actions, destroyed on every path.
class SpawnActions {
 public:
  SpawnActions() { posix_spawn_file_actions_init(&actions_); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions_); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_;
};

// Starts `args` with stdin from `stdin_fd` (-1: /dev/null), stdout to /dev/null and stderr to
// `log` ("" : /dev/null). Returns the pid, or -1 with errno set.
pid_t Spawn(const std::vector<std::string>& args, int stdin_fd, const std::string& log) {
  SpawnActions actions;
  if (stdin_fd >= 0)
    posix_spawn_file_actions_adddup2(actions.get(), stdin_fd, 0);
  else
    posix_spawn_file_actions_addopen(actions.get(), 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(actions.get(), 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(actions.get(), 2, log.empty() ? "/dev/null" : log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, argv[0], actions.get(), nullptr, argv.data(), environ);
  if (error != 0) {
    errno = error;
    return -1;
  }
  return pid;
}

// The exit status of `pid` (waits); -1 when it did not exit normally.
int WaitExit(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

std::optional<VideoFormat> ParseVideoFormat(const std::string& name) {
  if (name == "mp4") return VideoFormat::kMp4;
  if (name == "gif") return VideoFormat::kGif;
  if (name == "png") return VideoFormat::kPng;
  return std::nullopt;
}

std::string VideoExtension(VideoFormat format) {
  switch (format) {
    case VideoFormat::kMp4: return "mp4";
    case VideoFormat::kGif: return "gif";
    case VideoFormat::kPng: return "";
  }
  return "";
}

bool FfmpegAvailable(const std::string& ffmpeg) {
  const pid_t pid = Spawn({ffmpeg, "-version"}, -1, "");
  return pid > 0 && WaitExit(pid) == 0;
}

void WritePng(const std::string& path, const uint8_t* rgb, int width, int height) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw VideoError("cannot write " + path + ": " + std::strerror(errno));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw VideoError("libpng: out of memory");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw VideoError("libpng failed writing " + path);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, const_cast<png_bytep>(rgb + static_cast<size_t>(y) * width * 3));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

VideoWriter::VideoWriter(const std::string& path, int width, int height, const VideoOptions& options)
    : path_(path), width_(width), height_(height), options_(options) {
  if (width <= 0 || height <= 0 || width % 2 || height % 2)
    throw std::invalid_argument("video: frame size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is not even and positive");
  if (options.fps < 1 || options.fps > 240) throw std::invalid_argument("video: fps outside [1, 240]");
  if (options_.format == VideoFormat::kPng) {
    std::error_code error;
    std::filesystem::create_directories(path_, error);
    if (error) throw VideoError("cannot create " + path_ + ": " + error.message());
    return;
  }
  std::vector<std::string> args = {options_.ffmpeg,
                                   "-hide_banner",
                                   "-loglevel",
                                   "error",
                                   "-y",
                                   "-f",
                                   "rawvideo",
                                   "-pix_fmt",
                                   "rgb24",
                                   "-s",
                                   std::to_string(width) + "x" + std::to_string(height),
                                   "-r",
                                   std::to_string(options_.fps),
                                   "-i",
                                   "pipe:0"};
  if (options_.format == VideoFormat::kMp4) {
    args.insert(args.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-preset", "veryfast", "-crf", "20", "-movflags",
                             "+faststart"});
  } else {
    // one palette for the whole clip, made from the clip itself
    const std::string scale =
        options_.gif_width > 0 ? "scale=" + std::to_string(options_.gif_width) + ":-2:flags=lanczos," : "";
    args.insert(args.end(),
                {"-vf", scale + "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse", "-loop", "0"});
  }
  args.push_back(path_);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw VideoError(std::string("pipe: ") + std::strerror(errno));
  pid_ = Spawn(args, fds[0], path_ + ".log");
  const int spawn_errno = errno;
  close(fds[0]);
  if (pid_ < 0) {
    close(fds[1]);
    throw VideoError("cannot start " + options_.ffmpeg + ": " + std::strerror(spawn_errno) +
                     " (Debian: deploy/install-deps.sh video, or --format png)");
  }
  pipe_ = fds[1];
}

VideoWriter::~VideoWriter() {
  try {
    Close();
  } catch (const std::exception&) {
  }
}

std::string VideoWriter::FfmpegMessage() const {
  std::ifstream log(path_ + ".log");
  std::stringstream text;
  text << log.rdbuf();
  std::string message = text.str();
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message.empty() ? "no message" : message;
}

void VideoWriter::Write(const uint8_t* rgb) {
  if (closed_) throw VideoError(path_ + ": write after Close");
  if (options_.format == VideoFormat::kPng) {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame-%05d.png", frames_);
    WritePng(path_ + name, rgb, width_, height_);
    ++frames_;
    return;
  }
  const size_t size = static_cast<size_t>(width_) * height_ * 3;
  SigpipeBlock block;
  for (size_t done = 0; done < size;) {
    const ssize_t n = write(pipe_, rgb + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = errno;
      if (error == EPIPE) block.set_broken();
      close(pipe_);
      pipe_ = -1;
      WaitExit(pid_);
      pid_ = -1;
      closed_ = true;
      throw VideoError(path_ + ": ffmpeg stopped reading frames (" + std::strerror(error) + "): " + FfmpegMessage());
    }
    done += static_cast<size_t>(n);
  }
  ++frames_;
}

void VideoWriter::Close() {
  if (closed_) return;
  closed_ = true;
  if (pid_ < 0) return;
  close(pipe_);
  pipe_ = -1;
  const int status = WaitExit(pid_);
  pid_ = -1;
  if (status != 0)
    throw VideoError(path_ + ": ffmpeg failed (exit " + std::to_string(status) + "): " + FfmpegMessage());
  std::filesystem::remove(path_ + ".log");
}

}  // namespace srics::env
