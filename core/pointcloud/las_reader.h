// LasReader: reads uncompressed ASPRS LAS 1.0-1.4 files, point data formats 0-10, by hand.
//
// What is read: the public header (1.0-1.2: 227 bytes, 1.3: 235, 1.4: 375), the VLRs and the
// 1.4 EVLRs for the CRS (the OGC WKT record LASF_Projection/2112 first, else the GeoKeyDirectory
// LASF_Projection/34735's ProjectedCSTypeGeoKey 3072 or GeographicTypeGeoKey 2048 as an EPSG
// code), and per point x, y, z (scaled), classification and return number. Everything else
// (intensity, GPS time, colour, waveforms) is skipped. LAZ files are refused with a message that
// says how to decompress them. Stateless functions; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/base/status.h"
#include "core/pointcloud/point_cloud.h"

namespace tinbase {

struct LasHeader {
  uint8_t version_major = 1;
  uint8_t version_minor = 0;
  uint16_t header_size = 0;
  uint32_t point_offset = 0;  // offset to point data
  uint32_t vlr_count = 0;
  uint8_t point_format = 0;  // 0-10, compression bits cleared
  uint16_t record_length = 0;
  uint64_t point_count = 0;  // the 1.4 64-bit count when set, else the legacy 32-bit one
  std::array<double, 3> scale{};
  std::array<double, 3> offset{};
  std::array<double, 3> min{};  // x, y, z bounds as the header states them
  std::array<double, 3> max{};
  uint64_t evlr_offset = 0;  // 1.4 only
  uint32_t evlr_count = 0;
};

struct LasFile {
  LasHeader header;
  PointCloud cloud;
};

// The smallest public header size of LAS 1.`minor` (227, 235 or 375 bytes).
uint16_t LasMinimumHeaderSize(uint8_t minor);
// The bytes a record of point format `format` needs (0: 20 ... 10: 67). REQUIRES: format <= 10.
uint16_t LasMinimumRecordLength(uint8_t format);

// Reads the header alone. Errors name the file: IOError when it cannot be read; InvalidArgument
// when it is not LAS ("not a LAS file (signature 'XXXX', expected 'LASF')"), is LAZ, has an
// unknown version or point format, a header smaller than its version's or a record length
// smaller than its format's; Corruption when the points do not fit in the file (truncated).
Result<LasHeader> ReadLasHeader(const std::string& path);

// Reads the header, CRS and every point. Errors as ReadLasHeader, plus Corruption naming the
// point when a scaled coordinate is not finite, and InvalidArgument when a CRS record cannot be
// understood.
Result<LasFile> ReadLas(const std::string& path);

}  // namespace tinbase
