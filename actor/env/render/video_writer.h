#pragma once
// Frames into a video: MP4 (H.264) or GIF written by Debian's ffmpeg through a pipe, or,
// without ffmpeg, one PNG file per frame (libpng).
//
//   VideoWriter video("episode-000.mp4", 640, 480, {.format = VideoFormat::kMp4, .fps = 10});
//   for (...) video.Write(image.rgb.data());
//   video.Close();   // waits for ffmpeg; throws with its message when it failed
//
// An ffmpeg that died is a VideoError here, never a SIGPIPE: writes block SIGPIPE on the
// calling thread.

#include <sys/types.h>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace srics::env {

class VideoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class VideoFormat {
  kMp4,  // H.264 in MP4 (ffmpeg)
  kGif,  // an animated GIF with its own palette (ffmpeg)
  kPng,  // a folder of frame-00000.png, ... (no ffmpeg needed)
};

// "mp4", "gif", "png" -> the format; empty for anything else.
std::optional<VideoFormat> ParseVideoFormat(const std::string& name);
// The file name extension of a format ("mp4", "gif"; "" for PNG frames: a folder).
std::string VideoExtension(VideoFormat format);

struct VideoOptions {
  VideoFormat format = VideoFormat::kMp4;
  int fps = 10;                   // frames per second (an env step is 0.1 s: 10 is real time)
  int gif_width = 0;              // GIF only: scaled to this width (0: the frames' width)
  std::string ffmpeg = "ffmpeg";  // the program (looked up on the PATH)
};

// True when `ffmpeg -version` runs.
bool FfmpegAvailable(const std::string& ffmpeg = "ffmpeg");

// Writes an RGB image (rows top to bottom) as a PNG file. Throws VideoError.
void WritePng(const std::string& path, const uint8_t* rgb, int width, int height);

class VideoWriter {
 public:
  // `path`: the video file, or for PNG frames the folder (created). Starts ffmpeg for MP4 and
  // GIF (its messages go to <path>.log, removed when it succeeds). Throws VideoError when
  // ffmpeg cannot be started or the folder not created; std::invalid_argument for sizes that
  // are not even and positive or fps outside [1, 240].
  VideoWriter(const std::string& path, int width, int height, const VideoOptions& options);
  // Closes as Close() does but never throws (a failure is only lost: call Close()).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // One frame of width x height x 3 bytes. Throws VideoError when ffmpeg stopped reading
  // (with its message) or a PNG cannot be written.
  void Write(const uint8_t* rgb);
  // Ends the video: closes the pipe and waits for ffmpeg. Throws VideoError with ffmpeg's
  // message and exit status when it failed. Idempotent.
  void Close();

  int frames() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  std::string FfmpegMessage() const;

  std::string path_;
  int width_, height_;
  VideoOptions options_;
  int pipe_ = -1;   // ffmpeg's stdin
  pid_t pid_ = -1;  // ffmpeg
  int frames_ = 0;
  bool closed_ = false;
};

}  // namespace srics::env
