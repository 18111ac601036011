#include "core/query/profile_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/vector/gdal_session.h"

namespace tinbase {

namespace {

constexpr int kLeftMargin = 70;  // room for the z labels
constexpr int kRightMargin = 20;
constexpr int kTopMargin = 20;
constexpr int kBottomMargin = 36;  // room for the distance labels
constexpr int kGlyphScale = 2;     // font pixels per glyph bit
constexpr int kMaxSide = 16384;    // pixels: the image is drawn in memory, 3 bytes a pixel

using Rgb = std::array<uint8_t, 3>;
constexpr Rgb kGrid{225, 225, 225};
constexpr Rgb kFrame{90, 90, 90};
constexpr Rgb kText{40, 40, 40};
constexpr Rgb kHidden{160, 160, 160};

// A 3 x 5 pixel font of what numbers need; each row's bits from left to right.
struct Glyph {
  char c;
  std::array<uint8_t, 5> rows;
};
constexpr std::array<Glyph, 15> kFont{{
    {'0', {7, 5, 5, 5, 7}},
    {'1', {2, 6, 2, 2, 7}},
    {'2', {7, 1, 7, 4, 7}},
    {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}},
    {'5', {7, 4, 7, 1, 7}},
    {'6', {7, 4, 7, 5, 7}},
    {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}},
    {'9', {7, 5, 7, 1, 7}},
    {'.', {0, 0, 0, 0, 2}},
    {'-', {0, 0, 7, 0, 0}},
    {'e', {0, 7, 7, 4, 7}},
    {'+', {0, 2, 7, 2, 0}},
    {'m', {0, 0, 7, 7, 5}},
}};

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height * 3, 255) {}

  void Set(int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const size_t at = (static_cast<size_t>(y) * width_ + x) * 3;
    std::copy(c.begin(), c.end(), pixels_.begin() + static_cast<std::ptrdiff_t>(at));
  }

  // A line `thickness` pixels wide; with `dash` > 0, drawn in dashes of that many pixels.
  void Line(double x0, double y0, double x1, double y1, const Rgb& c, int thickness, int dash) {
    const int steps = static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0))));
    for (int s = 0; s <= steps; ++s) {
      if (dash > 0 && (s / dash) % 2 == 1) continue;
      const double f = steps == 0 ? 0 : static_cast<double>(s) / steps;
      const int x = static_cast<int>(std::lround(x0 + f * (x1 - x0)));
      const int y = static_cast<int>(std::lround(y0 + f * (y1 - y0)));
      for (int dy = 0; dy < thickness; ++dy)
        for (int dx = 0; dx < thickness; ++dx)
          Set(x + dx - thickness / 2, y + dy - thickness / 2, c);
    }
  }

  // Text with its top-left corner at (x, y); characters without a glyph are left blank.
  void Text(int x, int y, const std::string& text, const Rgb& c) {
    for (char ch : text) {
      for (const Glyph& g : kFont) {
        if (g.c != ch) continue;
        for (int row = 0; row < 5; ++row)
          for (int bit = 0; bit < 3; ++bit)
            if (g.rows[row] & (4 >> bit))
              for (int sy = 0; sy < kGlyphScale; ++sy)
                for (int sx = 0; sx < kGlyphScale; ++sx)
                  Set(x + bit * kGlyphScale + sx, y + row * kGlyphScale + sy, c);
      }
      x += 4 * kGlyphScale;
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::vector<uint8_t>& pixels() { return pixels_; }

 private:
  int width_, height_;
  std::vector<uint8_t> pixels_;  // row by row, RGB interleaved
};

int TextWidth(const std::string& text) { return static_cast<int>(text.size()) * 4 * kGlyphScale; }

// A round step (1, 2 or 5 times a power of ten) giving about `ticks` intervals over `range`.
double NiceStep(double range, int ticks) {
  const double raw = range / ticks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10 * power;
}

std::string Label(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", std::abs(value) < 1e-9 ? 0.0 : value);
  return buf;
}

Rgb Lighter(const Rgb& c) {
  Rgb out;
  for (int i = 0; i < 3; ++i) out[i] = static_cast<uint8_t>(255 - (255 - c[i]) * 30 / 100);
  return out;
}

void DrawGrid(Canvas& canvas, const ProfilePlotFrame& f) {
  const double z_step = NiceStep(f.max_z - f.min_z, 5);
  for (double z = std::ceil(f.min_z / z_step) * z_step; z <= f.max_z + z_step * 1e-9; z += z_step) {
    const double row = f.Row(z);
    canvas.Line(f.left, row, f.right, row, kGrid, 1, 0);
    const std::string text = Label(z);
    canvas.Text(f.left - 6 - TextWidth(text), static_cast<int>(row) - 5, text, kText);
  }
  const double d_step = NiceStep(f.length, 8);
  for (double d = 0; d <= f.length + d_step * 1e-9; d += d_step) {
    const double column = f.Column(d);
    canvas.Line(column, f.top, column, f.bottom, kGrid, 1, 0);
    const std::string text = Label(d);
    canvas.Text(static_cast<int>(column) - TextWidth(text) / 2, f.bottom + 8, text, kText);
  }
}

void DrawFrame(Canvas& canvas, const ProfilePlotFrame& f) {
  canvas.Line(f.left, f.top, f.right, f.top, kFrame, 1, 0);
  canvas.Line(f.left, f.bottom, f.right, f.bottom, kFrame, 1, 0);
  canvas.Line(f.left, f.top, f.left, f.bottom, kFrame, 1, 0);
  canvas.Line(f.right, f.top, f.right, f.bottom, kFrame, 1, 0);
}

// Shades the ground below each visible stretch in a light shade of its colour.
void DrawGround(Canvas& canvas, const ProfilePlotFrame& f, const std::vector<Station>& stations,
                const std::vector<ProfilePlotStretch>& stretches) {
  size_t i = 0;
  for (int column = f.left + 1; column < f.right; ++column) {
    const double d = f.length * (column - f.left) / (f.right - f.left);
    while (i + 1 < stretches.size() && stations[i + 1].distance < d) ++i;
    if (!stretches[i].visible) continue;
    const Station &a = stations[i], &b = stations[i + 1];
    const double span = b.distance - a.distance;
    const double z = span > 0 ? a.z + (b.z - a.z) * (d - a.distance) / span : a.z;
    const Rgb shade = Lighter(SeriesColour(stretches[i].series));
    for (int row = static_cast<int>(std::ceil(f.Row(z))); row < f.bottom; ++row)
      canvas.Set(column, row, shade);
  }
}

void DrawProfile(Canvas& canvas, const ProfilePlotFrame& f, const std::vector<Station>& stations,
                 const std::vector<ProfilePlotStretch>& stretches) {
  for (size_t i = 0; i < stretches.size(); ++i) {
    const Station &a = stations[i], &b = stations[i + 1];
    const bool visible = stretches[i].visible;
    canvas.Line(f.Column(a.distance), f.Row(a.z), f.Column(b.distance), f.Row(b.z),
                visible ? SeriesColour(stretches[i].series) : kHidden, 2, visible ? 0 : 6);
  }
}

Status WritePng(Canvas& canvas, const std::string& path) {
  RegisterGdalDriversOnce();
  QuietGdalErrors quiet;
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
  if (mem == nullptr || png == nullptr) return Status::IOError(path + ": GDAL has no PNG driver");
  GdalDatasetPtr image(mem->Create("", canvas.width(), canvas.height(), 3, GDT_Byte, nullptr));
  if (!image) return Status::IOError(path + ": cannot make the image" + LastGdalError());
  int bands[3] = {1, 2, 3};
  // Pixel-interleaved RGB: 3 bytes a pixel, a row of them a line, 1 byte between bands.
  if (image->RasterIO(GF_Write, 0, 0, canvas.width(), canvas.height(), canvas.pixels().data(),
                      canvas.width(), canvas.height(), GDT_Byte, 3, bands, 3,
                      static_cast<GSpacing>(canvas.width()) * 3, 1, nullptr) != CE_None)
    return Status::IOError(path + ": cannot draw the image" + LastGdalError());
  GdalDatasetPtr written(
      png->CreateCopy(path.c_str(), image.get(), FALSE, nullptr, nullptr, nullptr));
  if (!written) return Status::IOError(path + ": cannot write the PNG" + LastGdalError());
  return Status::Ok();
}

}  // namespace

double ProfilePlotFrame::Column(double d) const {
  return left + (right - left) * (length > 0 ? d / length : 0);
}

double ProfilePlotFrame::Row(double z) const {
  return bottom - (bottom - top) * (z - min_z) / (max_z - min_z);
}

ProfilePlotFrame PlotFrameFor(const std::vector<Station>& stations,
                              const ProfilePlotOptions& options) {
  ProfilePlotFrame f;
  f.left = kLeftMargin;
  f.right = options.width - 1 - kRightMargin;
  f.top = kTopMargin;
  f.bottom = options.height - 1 - kBottomMargin;
  f.length = stations.back().distance;
  double lo = stations.front().z, hi = lo;
  for (const Station& s : stations) lo = std::min(lo, s.z), hi = std::max(hi, s.z);
  const double pad = hi > lo ? (hi - lo) * 0.05 : 1.0;
  const double step = NiceStep(hi - lo + 2 * pad, 5);
  f.min_z = std::floor((lo - pad) / step) * step;
  f.max_z = std::ceil((hi + pad) / step) * step;
  return f;
}

std::array<uint8_t, 3> SeriesColour(int series) {
  // Tableau's ten categorical colours: distinct on screen and in print.
  static constexpr std::array<Rgb, 10> kPalette{{{31, 119, 180},
                                                 {255, 127, 14},
                                                 {44, 160, 44},
                                                 {214, 39, 40},
                                                 {148, 103, 189},
                                                 {140, 86, 75},
                                                 {227, 119, 194},
                                                 {188, 189, 34},
                                                 {23, 190, 207},
                                                 {127, 127, 127}}};
  if (series < 0) return {60, 60, 60};
  return kPalette[static_cast<size_t>(series) % kPalette.size()];
}

Status WriteProfilePlot(const std::vector<Station>& stations,
                        const std::vector<ProfilePlotStretch>& stretches, const std::string& path,
                        const ProfilePlotOptions& options) {
  if (options.width < 200 || options.height < 100 || options.width > kMaxSide ||
      options.height > kMaxSide)
    return Status::InvalidArgument("a profile plot has 200 x 100 to " + std::to_string(kMaxSide) +
                                   " x " + std::to_string(kMaxSide) + " pixels, not " +
                                   std::to_string(options.width) + " x " +
                                   std::to_string(options.height));
  if (stations.size() < 2 || stretches.size() + 1 != stations.size())
    return Status::InvalidArgument("a profile plot needs one stretch between each two stations");
  Canvas canvas(options.width, options.height);
  const ProfilePlotFrame frame = PlotFrameFor(stations, options);
  DrawGrid(canvas, frame);
  DrawGround(canvas, frame, stations, stretches);
  DrawProfile(canvas, frame, stations, stretches);
  DrawFrame(canvas, frame);
  return WritePng(canvas, path);
}

}  // namespace tinbase
