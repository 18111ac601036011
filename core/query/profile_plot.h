// ProfilePlot: a terrain profile drawn as a PNG image, z against distance along the line, each
// stretch in the colour of its tag with the ground below it shaded, hidden stretches dashed
// grey, and the z and distance scales labelled.
//
// The pixels are drawn here into memory and written through GDAL's PNG driver (the reader every
// GIS uses for the file). Stateless; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/query/line_walk.h"

namespace tinbase {

struct ProfilePlotStretch {
  int series = -1;  // colour index (a tag's position among the tags), -1 for no tag
  bool visible = true;
};

struct ProfilePlotOptions {
  int width = 1000;  // pixels
  int height = 400;
};

// Where data lands in the image: the plot area's pixel bounds and the data range it shows.
struct ProfilePlotFrame {
  int left = 0, right = 0, top = 0, bottom = 0;  // pixel columns / rows of the plot area
  double length = 0;                             // distance at the right edge (0 at the left)
  double min_z = 0, max_z = 0;                   // z at the bottom and top edges
  // Pixel column of distance d, row of height z.
  double Column(double d) const;
  double Row(double z) const;
};

// The frame the plot of `stations` uses: z padded by 5 % of its range (or 1 when flat) and
// rounded out to the grid step. REQUIRES: at least two stations.
ProfilePlotFrame PlotFrameFor(const std::vector<Station>& stations,
                              const ProfilePlotOptions& options);

// The RGB colour of series `series` (-1: no tag).
std::array<uint8_t, 3> SeriesColour(int series);

// Writes the plot of `stations` (stretches[i] from stations[i] to stations[i + 1]) as a PNG
// file at `path`, overwriting it. InvalidArgument when the options ask for an image under
// 200 x 100 pixels or over 16384 on a side, or the counts do not match; IOError naming the path
// when GDAL cannot write. REQUIRES: at least two stations, finite values.
Status WriteProfilePlot(const std::vector<Station>& stations,
                        const std::vector<ProfilePlotStretch>& stretches, const std::string& path,
                        const ProfilePlotOptions& options = {});

}  // namespace tinbase
