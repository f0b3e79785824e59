#include "actor/env/episode_drawing.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "actor/env/mjcf.h"

namespace srics::env {
namespace {

using Rgb = std::array<double, 3>;

constexpr double kPixelsPerMetre = 1200;
constexpr double kBorder = 0.02;  // metres of margin around the walls
const Rgb kTable{0.93, 0.93, 0.90};
const Rgb kWall{0.45, 0.45, 0.40};
const Rgb kHand{0.15, 0.15, 0.15};
const Rgb kBackground{1, 1, 1};

// World-to-picture mapping: x to the right, y up.
struct Frame {
  double x0, y0, x1, y1;  // world box drawn
  int width() const { return static_cast<int>(std::ceil((x1 - x0) * kPixelsPerMetre)); }
  int height() const { return static_cast<int>(std::ceil((y1 - y0) * kPixelsPerMetre)); }
  double px(double x) const { return (x - x0) * kPixelsPerMetre; }
  double py(double y) const { return (y1 - y) * kPixelsPerMetre; }
};

Frame MakeFrame(const config::EnvConfig& c) {
  const auto& t = c.table;
  const double th = t.wall_half_thickness;
  return {-t.wall_x - th - kBorder, t.wall_y_low - th - kBorder, t.wall_x + th + kBorder, t.wall_y_high + th + kBorder};
}

// A tiny software rasterizer with 4x4 supersampled coverage for smooth edges.
class Canvas {
 public:
  Canvas(int w, int h, Rgb fill) : w_(w), h_(h), pixels_(static_cast<size_t>(w) * h, fill) {}

  // Blends `color` with opacity `alpha` wherever inside(x, y) holds (pixel coordinates),
  // limited to the bounding box [x0, x1] x [y0, y1].
  template <typename Inside>
  void Fill(double x0, double y0, double x1, double y1, Rgb color, double alpha, Inside inside) {
    const int i0 = std::max(0, static_cast<int>(std::floor(x0)));
    const int i1 = std::min(w_ - 1, static_cast<int>(std::ceil(x1)));
    const int j0 = std::max(0, static_cast<int>(std::floor(y0)));
    const int j1 = std::min(h_ - 1, static_cast<int>(std::ceil(y1)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        int hits = 0;
        for (int sy = 0; sy < 4; ++sy)
          for (int sx = 0; sx < 4; ++sx) hits += inside(i + (sx + 0.5) / 4, j + (sy + 0.5) / 4) ? 1 : 0;
        if (hits == 0) continue;
        const double a = alpha * hits / 16.0;
        Rgb& p = pixels_[static_cast<size_t>(j) * w_ + i];
        for (int k = 0; k < 3; ++k) p[k] = p[k] * (1 - a) + color[k] * a;
      }
    }
  }

  void Disc(double cx, double cy, double r, Rgb color, double alpha = 1) {
    Fill(cx - r, cy - r, cx + r, cy + r, color, alpha,
         [&](double x, double y) { return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r; });
  }
  void Ring(double cx, double cy, double r, double width, Rgb color, double alpha = 1) {
    const double ro = r + width / 2, ri = r - width / 2;
    Fill(cx - ro, cy - ro, cx + ro, cy + ro, color, alpha, [&](double x, double y) {
      const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
      return d2 <= ro * ro && d2 >= ri * ri;
    });
  }
  void Rect(double x0, double y0, double x1, double y1, Rgb color, double alpha = 1) {
    Fill(x0, y0, x1, y1, color, alpha, [&](double x, double y) { return x >= x0 && x <= x1 && y >= y0 && y <= y1; });
  }
  void RectOutline(double x0, double y0, double x1, double y1, double width, Rgb color) {
    Rect(x0 - width / 2, y0 - width / 2, x1 + width / 2, y0 + width / 2, color);
    Rect(x0 - width / 2, y1 - width / 2, x1 + width / 2, y1 + width / 2, color);
    Rect(x0 - width / 2, y0, x0 + width / 2, y1, color);
    Rect(x1 - width / 2, y0, x1 + width / 2, y1, color);
  }
  void Line(double ax, double ay, double bx, double by, double width, Rgb color, double alpha = 1) {
    const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    const double r = width / 2;
    Fill(std::min(ax, bx) - r, std::min(ay, by) - r, std::max(ax, bx) + r, std::max(ay, by) + r, color, alpha,
         [&](double x, double y) {
           double t = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0;
           t = std::clamp(t, 0.0, 1.0);
           const double ex = ax + t * dx - x, ey = ay + t * dy - y;
           return ex * ex + ey * ey <= r * r;
         });
  }

  void WritePng(const std::string& path, const std::string& title) const {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!file) throw std::runtime_error("cannot write " + path);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      throw std::runtime_error("libpng: out of memory");
    }
    std::vector<unsigned char> row(static_cast<size_t>(w_) * 3);
    if (setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      throw std::runtime_error("libpng failed writing " + path);
    }
    png_init_io(png, file.get());
    png_set_IHDR(png, info, w_, h_, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_text text{};
    std::string key = "Title", value = title;
    text.compression = PNG_TEXT_COMPRESSION_NONE;
    text.key = key.data();
    text.text = value.data();
    if (!title.empty()) png_set_text(png, info, &text, 1);
    png_write_info(png, info);
    for (int j = 0; j < h_; ++j) {
      for (int i = 0; i < w_; ++i)
        for (int k = 0; k < 3; ++k)
          row[static_cast<size_t>(i) * 3 + k] = static_cast<unsigned char>(
              std::lround(255 * std::clamp(pixels_[static_cast<size_t>(j) * w_ + i][k], 0.0, 1.0)));
      png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
  }

 private:
  int w_, h_;
  std::vector<Rgb> pixels_;
};

void CheckTrace(const EpisodeTrace& t) {
  const size_t n = t.present.size() + 1;
  if (t.goals.size() != n) throw std::runtime_error("DrawEpisode: one goal per entity expected");
  if (t.positions.empty()) throw std::runtime_error("DrawEpisode: no positions");
  for (const auto& step : t.positions)
    if (step.size() != n) throw std::runtime_error("DrawEpisode: one position per entity expected");
}

int EntityOf(const EpisodeTrace& t, int catalogue) {
  for (size_t k = 0; k < t.present.size(); ++k)
    if (t.present[k] == catalogue) return static_cast<int>(k) + 1;
  return -1;
}

void DrawPng(const EpisodeTrace& t, const std::string& path) {
  const config::EnvConfig& c = t.config;
  const auto objects = config::EffectiveObjects(c);
  const Frame f = MakeFrame(c);
  Canvas canvas(f.width(), f.height(), kBackground);
  const double s = kPixelsPerMetre;
  const auto& tb = c.table;
  const double th = tb.wall_half_thickness;

  // table between the walls, the walls, the object box (thin)
  canvas.Rect(f.px(-tb.wall_x), f.py(tb.wall_y_high), f.px(tb.wall_x), f.py(tb.wall_y_low), kTable);
  canvas.RectOutline(f.px(-tb.wall_x), f.py(tb.wall_y_high), f.px(tb.wall_x), f.py(tb.wall_y_low), 2 * th * s, kWall);
  canvas.RectOutline(f.px(c.hand.mocap_low[0]), f.py(c.hand.mocap_high[1]), f.px(c.hand.mocap_high[0]),
                     f.py(c.hand.mocap_low[1]), 1, {0.7, 0.7, 0.7});

  // connections at the final step
  const auto& last = t.positions.back();
  for (const auto& k : c.connections) {
    const int a = EntityOf(t, k.first), b = EntityOf(t, k.second);
    if (a < 0 || b < 0) continue;
    canvas.Line(f.px(last[a][0]), f.py(last[a][1]), f.px(last[b][0]), f.py(last[b][1]), 3, {0.55, 0.35, 0.15});
  }

  // trajectories, faint to strong over time
  for (size_t e = 0; e < last.size(); ++e) {
    const Rgb color = e == 0 ? kHand : ObjectColor(c, t.present[e - 1]);
    for (size_t step = 1; step < t.positions.size(); ++step) {
      const auto& a = t.positions[step - 1][e];
      const auto& b = t.positions[step][e];
      canvas.Line(f.px(a[0]), f.py(a[1]), f.px(b[0]), f.py(b[1]), 2.5, color, 0.6);
    }
    const auto& start = t.positions.front()[e];
    canvas.Disc(f.px(start[0]), f.py(start[1]), 4, color, 0.8);
  }

  // objects at their final pose (boxes do not rotate: their inertia is huge)
  for (size_t k = 0; k < t.present.size(); ++k) {
    const auto& o = objects.at(t.present[k] - 1);
    const Rgb color = ObjectColor(c, t.present[k]);
    const auto& p = last[k + 1];
    const double r = o.size * s;
    if (o.shape == config::ObjectShape::kBox) {
      canvas.Rect(f.px(p[0]) - r, f.py(p[1]) - r, f.px(p[0]) + r, f.py(p[1]) + r, color, 0.85);
    } else {
      canvas.Disc(f.px(p[0]), f.py(p[1]), r, color, 0.85);
    }
    if (o.is_static) canvas.Disc(f.px(p[0]), f.py(p[1]), 0.3 * r, {0, 0, 0}, 0.8);
  }

  // hand at its final pose
  const auto& hs = c.hand.half_size;
  canvas.Rect(f.px(last[0][0] - hs[0]), f.py(last[0][1] + hs[1]), f.px(last[0][0] + hs[0]), f.py(last[0][1] - hs[1]),
              kHand, 0.9);

  // goals: rings of the object's size, a cross for the hand
  for (size_t k = 0; k < t.present.size(); ++k) {
    const auto& o = objects.at(t.present[k] - 1);
    const auto& g = t.goals[k + 1];
    canvas.Ring(f.px(g[0]), f.py(g[1]), o.size * s, 3, ObjectColor(c, t.present[k]));
    canvas.Ring(f.px(g[0]), f.py(g[1]), c.success_threshold * s, 1, {0.3, 0.3, 0.3});
  }
  const auto& hg = t.goals[0];
  canvas.Line(f.px(hg[0]) - 8, f.py(hg[1]) - 8, f.px(hg[0]) + 8, f.py(hg[1]) + 8, 3, kHand);
  canvas.Line(f.px(hg[0]) - 8, f.py(hg[1]) + 8, f.px(hg[0]) + 8, f.py(hg[1]) - 8, 3, kHand);
  canvas.WritePng(path, t.title);
}

std::string Hex(const Rgb& c) {
  char text[8];
  std::snprintf(text, sizeof(text), "#%02x%02x%02x", static_cast<int>(std::lround(255 * c[0])),
                static_cast<int>(std::lround(255 * c[1])), static_cast<int>(std::lround(255 * c[2])));
  return text;
}

void DrawSvg(const EpisodeTrace& t, const std::string& path) {
  const config::EnvConfig& c = t.config;
  const auto objects = config::EffectiveObjects(c);
  const Frame f = MakeFrame(c);
  const double s = kPixelsPerMetre;
  const auto& tb = c.table;
  const double th = tb.wall_half_thickness;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << f.width() << "\" height=\"" << f.height() + 24
    << "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!t.title.empty())
    o << "<text x=\"6\" y=\"" << f.height() + 18 << "\" font-family=\"sans-serif\" font-size=\"14\">" << t.title
      << "</text>\n";
  o << "<rect x=\"" << f.px(-tb.wall_x) << "\" y=\"" << f.py(tb.wall_y_high) << "\" width=\"" << 2 * tb.wall_x * s
    << "\" height=\"" << (tb.wall_y_high - tb.wall_y_low) * s << "\" fill=\"" << Hex(kTable) << "\" stroke=\""
    << Hex(kWall) << "\" stroke-width=\"" << 2 * th * s << "\"/>\n";
  const auto& last = t.positions.back();
  for (const auto& k : c.connections) {
    const int a = EntityOf(t, k.first), b = EntityOf(t, k.second);
    if (a < 0 || b < 0) continue;
    o << "<line x1=\"" << f.px(last[a][0]) << "\" y1=\"" << f.py(last[a][1]) << "\" x2=\"" << f.px(last[b][0])
      << "\" y2=\"" << f.py(last[b][1]) << "\" stroke=\"#8c5926\" stroke-width=\"3\"/>\n";
  }
  for (size_t e = 0; e < last.size(); ++e) {
    const Rgb color = e == 0 ? kHand : ObjectColor(c, t.present[e - 1]);
    o << "<polyline fill=\"none\" stroke=\"" << Hex(color)
      << "\" stroke-opacity=\"0.6\" stroke-width=\"2.5\" points=\"";
    for (const auto& step : t.positions) o << f.px(step[e][0]) << "," << f.py(step[e][1]) << " ";
    o << "\"/>\n";
  }
  for (size_t k = 0; k < t.present.size(); ++k) {
    const auto& obj = objects.at(t.present[k] - 1);
    const auto& p = last[k + 1];
    const auto& g = t.goals[k + 1];
    const std::string color = Hex(ObjectColor(c, t.present[k]));
    const double r = obj.size * s;
    if (obj.shape == config::ObjectShape::kBox) {
      o << "<rect x=\"" << f.px(p[0]) - r << "\" y=\"" << f.py(p[1]) - r << "\" width=\"" << 2 * r << "\" height=\""
        << 2 * r << "\" fill=\"" << color << "\" fill-opacity=\"0.85\"/>\n";
    } else {
      o << "<circle cx=\"" << f.px(p[0]) << "\" cy=\"" << f.py(p[1]) << "\" r=\"" << r << "\" fill=\"" << color
        << "\" fill-opacity=\"0.85\"/>\n";
    }
    o << "<circle cx=\"" << f.px(g[0]) << "\" cy=\"" << f.py(g[1]) << "\" r=\"" << r << "\" fill=\"none\" stroke=\""
      << color << "\" stroke-width=\"3\"/>\n";
  }
  const auto& hs = c.hand.half_size;
  o << "<rect x=\"" << f.px(last[0][0] - hs[0]) << "\" y=\"" << f.py(last[0][1] + hs[1]) << "\" width=\""
    << 2 * hs[0] * s << "\" height=\"" << 2 * hs[1] * s << "\" fill=\"" << Hex(kHand) << "\"/>\n";
  const auto& hg = t.goals[0];
  o << "<path d=\"M" << f.px(hg[0]) - 8 << "," << f.py(hg[1]) - 8 << " l16,16 m0,-16 l-16,16\" "
    << "stroke=\"" << Hex(kHand) << "\" stroke-width=\"3\"/>\n</svg>\n";
  std::ofstream file(path);
  if (!(file << o.str())) throw std::runtime_error("cannot write " + path);
}

}  // namespace

void DrawEpisode(const EpisodeTrace& trace, const std::string& path) {
  CheckTrace(trace);
  const auto ends_with = [&](const std::string& suffix) {
    return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".png")) return DrawPng(trace, path);
  if (ends_with(".svg")) return DrawSvg(trace, path);
  throw std::runtime_error("DrawEpisode: " + path + ": expected a .png or .svg file name");
}

}  // namespace srics::env
