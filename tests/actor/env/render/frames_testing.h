#pragma once
// Reading frames back and measuring them: PNG files (libpng), raw RGB decoded by ffmpeg, and
// the hand's place in a frame (the renderer's tests and the srics eval test share them).

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "actor/env/render/episode_renderer.h"

namespace srics::env::testing {

// A PNG file as an RGB image (8-bit RGB files only, as WritePng writes them); empty on error.
inline std::optional<Image> ReadPng(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return std::nullopt;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  Image image;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return std::nullopt;
  }
  png_init_io(png, file);
  png_read_info(png, info);
  if (png_get_color_type(png, info) != PNG_COLOR_TYPE_RGB || png_get_bit_depth(png, info) != 8) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return std::nullopt;
  }
  image.width = static_cast<int>(png_get_image_width(png, info));
  image.height = static_cast<int>(png_get_image_height(png, info));
  image.rgb.resize(static_cast<size_t>(image.width) * image.height * 3);
  for (int y = 0; y < image.height; ++y)
    png_read_row(png, image.rgb.data() + static_cast<size_t>(y) * image.width * 3, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  return image;
}

// Every frame of a video, decoded by ffmpeg to raw RGB of width x height.
inline std::vector<Image> DecodeVideo(const std::string& path, int width, int height, const std::string& scratch) {
  const std::string command = "ffmpeg -v error -y -i '" + path + "' -f rawvideo -pix_fmt rgb24 '" + scratch + "'";
  std::vector<Image> frames;
  if (std::system(command.c_str()) != 0) return frames;
  std::ifstream in(scratch, std::ios::binary);
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  const size_t frame_size = static_cast<size_t>(width) * height * 3;
  for (size_t at = 0; at + frame_size <= bytes.size(); at += frame_size)
    frames.push_back({width, height, {bytes.begin() + at, bytes.begin() + at + frame_size}});
  return frames;
}

// Standard deviation of all channel values (0 for a blank frame).
inline double PixelStdDev(const Image& image) {
  double sum = 0, squares = 0;
  for (uint8_t v : image.rgb) sum += v, squares += static_cast<double>(v) * v;
  const double n = static_cast<double>(image.rgb.size());
  return std::sqrt(std::max(0.0, squares / n - (sum / n) * (sum / n)));
}

// Pixels whose channels differ by more than `tolerance` somewhere (images of one size).
inline int DifferingPixels(const Image& a, const Image& b, int tolerance = 24) {
  int count = 0;
  for (size_t p = 0; p + 2 < a.rgb.size() && p + 2 < b.rgb.size(); p += 3) {
    int d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a.rgb[p + k]) - int(b.rgb[p + k])));
    if (d > tolerance) ++count;
  }
  return count;
}

// The hand in a frame: the centroid (x, y pixels) of the dark grey pixels (the hand is the only
// grey body, its top 80-90 and its sides 36 under the default lights; table and caption text are
// white, floor, caption box, objects and goal markers coloured); empty when fewer than
// `min_pixels` are found. `max_level`: the brightest channel value counted.
struct Blob {
  double x = 0, y = 0;
  int pixels = 0;
};
inline std::optional<Blob> FindHand(const Image& image, int max_level = 100, int min_pixels = 20) {
  Blob blob;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.rgb.data() + (static_cast<size_t>(y) * image.width + x) * 3;
      if (std::max({p[0], p[1], p[2]}) > max_level) continue;
      // grey, not a dark colour
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 12) continue;
      blob.x += x, blob.y += y, ++blob.pixels;
    }
  if (blob.pixels < min_pixels) return std::nullopt;
  blob.x /= blob.pixels, blob.y /= blob.pixels;
  return blob;
}

// Where a world point (metres) appears in a frame drawn with `options` (x right, y down, pixels):
// MuJoCo's free camera (looking at options.lookat from options.distance at the elevation and
// azimuth given) and its perspective (vertical field of view `fovy_degrees`, the model's
// vis.global.fovy, 45 by default; square pixels).
struct Pixel {
  double x = 0, y = 0;
};
inline Pixel PixelOf(const RenderOptions& options, double fovy_degrees, double wx, double wy, double wz) {
  constexpr double kDegree = 3.14159265358979323846 / 180;
  const double el = options.elevation * kDegree, az = options.azimuth * kDegree;
  const double forward[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  const double up[3] = {-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el)};
  const double right[3] = {forward[1] * up[2] - forward[2] * up[1], forward[2] * up[0] - forward[0] * up[2],
                           forward[0] * up[1] - forward[1] * up[0]};
  const double camera[3] = {options.lookat[0] - options.distance * forward[0],
                            options.lookat[1] - options.distance * forward[1], -options.distance * forward[2]};
  const double v[3] = {wx - camera[0], wy - camera[1], wz - camera[2]};
  auto dot = [&](const double* a) { return a[0] * v[0] + a[1] * v[1] + a[2] * v[2]; };
  const double focal = 0.5 * options.height / std::tan(0.5 * fovy_degrees * kDegree);
  const double depth = dot(forward);
  return {0.5 * options.width + focal * dot(right) / depth, 0.5 * options.height - focal * dot(up) / depth};
}

// The colour of pixel (x, y), rounded to the nearest pixel.
inline const uint8_t* PixelAt(const Image& image, double x, double y) {
  const int i = std::clamp(static_cast<int>(std::lround(x)), 0, image.width - 1);
  const int j = std::clamp(static_cast<int>(std::lround(y)), 0, image.height - 1);
  return image.rgb.data() + (static_cast<size_t>(j) * image.width + i) * 3;
}

}  // namespace srics::env::testing
