#include "core/pointcloud/las_reader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

namespace tinbase {
namespace {

// LAS is little-endian; fields are copied with memcpy, which is only right on such a host.
static_assert(std::endian::native == std::endian::little,
              "LAS reader assumes a little-endian host");

constexpr size_t kLegacyHeaderSize = 227;  // LAS 1.0-1.2
constexpr size_t kVlrHeaderSize = 54;
constexpr size_t kEvlrHeaderSize = 60;
constexpr uint16_t kWktRecordId = 2112;
constexpr uint16_t kGeoKeyDirectoryRecordId = 34735;
constexpr uint16_t kLaszipRecordId = 22204;
constexpr uint16_t kProjectedCsTypeGeoKey = 3072;
constexpr uint16_t kGeographicTypeGeoKey = 2048;
constexpr uint16_t kUserDefinedGeoKeyValue = 32767;
// Point format bits 6 and 7 mark LAZ (laszip sets bit 7; some writers set bit 6).
constexpr uint8_t kCompressionBits = 0xC0;

template <typename T>
T Get(const std::vector<char>& bytes, size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

std::string LazMessage() {
  return "is LAZ (compressed); tinbase reads uncompressed LAS: decompress it with laszip or pdal "
         "translate first";
}

struct Vlr {
  std::string user_id;
  uint16_t record_id = 0;
  std::vector<char> data;
};

// An open LAS file: its name for messages, its size, and a stream to read ranges from.
class LasSource {
 public:
  static Result<LasSource> Open(const std::string& path) {
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return Status::IOError(path + ": cannot read file: " + ec.message());
    LasSource source(path, size);
    if (!source.in_) return Status::IOError(path + ": cannot open file");
    return source;
  }

  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }

  // Reads `n` bytes at `offset`; Corruption naming `what` when the file ends first.
  Result<std::vector<char>> Read(uint64_t offset, uint64_t n, const std::string& what) {
    if (offset > size_ || n > size_ - offset) {
      return Status::Corruption(path_ + ": file ends inside the " + what + " (truncated: needs " +
                                std::to_string(offset + n) + " bytes, file has " +
                                std::to_string(size_) + ")");
    }
    std::vector<char> bytes(n);
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(bytes.data(), static_cast<std::streamsize>(n));
    if (!in_) return Status::IOError(path_ + ": read error in the " + what);
    return bytes;
  }

 private:
  LasSource(const std::string& path, uint64_t size)
      : path_(path), size_(size), in_(path, std::ios::binary) {}
  std::string path_;
  uint64_t size_;
  std::ifstream in_;
};

std::string TrimmedString(const std::vector<char>& bytes, size_t at, size_t n) {
  std::string s(bytes.data() + at, n);
  s.erase(std::find(s.begin(), s.end(), '\0'), s.end());
  return s;
}

// Decodes and validates the public header. The reader stops at the first problem and names it.
Result<LasHeader> DecodeHeader(LasSource& source, const std::vector<char>& bytes) {
  const std::string& path = source.path();
  if (bytes.size() < 4 || std::memcmp(bytes.data(), "LASF", 4) != 0) {
    std::string sig(bytes.data(), std::min<size_t>(bytes.size(), 4));
    for (char& c : sig) {
      if (c < 32 || c > 126) c = '?';
    }
    return Status::InvalidArgument(path + ": not a LAS file (signature '" + sig +
                                   "', expected 'LASF')");
  }
  if (bytes.size() < kLegacyHeaderSize) {
    return Status::Corruption(path + ": file ends inside the LAS header (truncated: " +
                              std::to_string(bytes.size()) + " bytes)");
  }
  LasHeader h;
  h.version_major = Get<uint8_t>(bytes, 24);
  h.version_minor = Get<uint8_t>(bytes, 25);
  const std::string version =
      "LAS " + std::to_string(h.version_major) + "." + std::to_string(h.version_minor);
  if (h.version_major != 1 || h.version_minor > 4) {
    return Status::InvalidArgument(path + ": unsupported version " + version +
                                   " (tinbase reads LAS 1.0 to 1.4)");
  }
  h.header_size = Get<uint16_t>(bytes, 94);
  h.point_offset = Get<uint32_t>(bytes, 96);
  h.vlr_count = Get<uint32_t>(bytes, 100);
  const uint8_t raw_format = Get<uint8_t>(bytes, 104);
  h.record_length = Get<uint16_t>(bytes, 105);
  if (raw_format & kCompressionBits) return Status::InvalidArgument(path + " " + LazMessage());
  h.point_format = raw_format;

  const uint16_t min_header = LasMinimumHeaderSize(h.version_minor);
  if (h.header_size < min_header) {
    return Status::InvalidArgument(path + ": header size " + std::to_string(h.header_size) +
                                   " is smaller than the " + std::to_string(min_header) +
                                   " bytes " + version + " requires");
  }
  if (bytes.size() < min_header) {
    return Status::Corruption(path + ": file ends inside the " + version +
                              " header (truncated: " + std::to_string(bytes.size()) + " bytes)");
  }
  if (h.point_format > 10) {
    return Status::InvalidArgument(path + ": unknown point data format " +
                                   std::to_string(h.point_format) + " (LAS knows 0 to 10)");
  }
  const uint16_t min_record = LasMinimumRecordLength(h.point_format);
  if (h.record_length < min_record) {
    return Status::InvalidArgument(path + ": point record length " +
                                   std::to_string(h.record_length) + " is smaller than the " +
                                   std::to_string(min_record) + " bytes point format " +
                                   std::to_string(h.point_format) + " needs");
  }
  if (h.point_offset < h.header_size) {
    return Status::Corruption(path + ": offset to point data " + std::to_string(h.point_offset) +
                              " lies inside the " + std::to_string(h.header_size) + "-byte header");
  }

  h.point_count = Get<uint32_t>(bytes, 107);
  static const char* kAxis[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    h.scale[i] = Get<double>(bytes, 131 + 8 * i);
    h.offset[i] = Get<double>(bytes, 155 + 8 * i);
    h.max[i] = Get<double>(bytes, 179 + 16 * i);
    h.min[i] = Get<double>(bytes, 187 + 16 * i);
    if (!std::isfinite(h.scale[i]) || h.scale[i] == 0 || !std::isfinite(h.offset[i])) {
      return Status::InvalidArgument(path + ": " + kAxis[i] + " scale factor " +
                                     std::to_string(h.scale[i]) + " or offset " +
                                     std::to_string(h.offset[i]) + " is unusable");
    }
  }
  if (h.version_minor >= 4) {
    h.evlr_offset = Get<uint64_t>(bytes, 235);
    h.evlr_count = Get<uint32_t>(bytes, 243);
    const uint64_t count64 = Get<uint64_t>(bytes, 247);
    if (count64 != 0) h.point_count = count64;
  }

  const uint64_t room = source.size() > h.point_offset ? source.size() - h.point_offset : 0;
  if (h.point_count > room / h.record_length) {
    return Status::Corruption(
        path + ": header promises " + std::to_string(h.point_count) + " points of " +
        std::to_string(h.record_length) + " bytes from offset " + std::to_string(h.point_offset) +
        ", but the file holds only " + std::to_string(room / h.record_length) + " (truncated)");
  }
  return h;
}

// The VLRs between the header and the points, and the 1.4 EVLRs after them. Only the records
// tinbase reads (LASF_Projection, laszip) keep their data; the others are skipped unread.
Result<std::vector<Vlr>> ReadVlrs(LasSource& source, const LasHeader& h) {
  std::vector<Vlr> vlrs;
  const auto wanted = [](const Vlr& v) {
    return v.user_id == "LASF_Projection" || v.user_id == "laszip encoded";
  };
  uint64_t at = h.header_size;
  for (uint32_t i = 0; i < h.vlr_count; ++i) {
    const std::string what = "variable length record " + std::to_string(i);
    TB_ASSIGN_OR_RETURN(std::vector<char> head, source.Read(at, kVlrHeaderSize, what));
    Vlr vlr{TrimmedString(head, 2, 16), Get<uint16_t>(head, 18), {}};
    const uint16_t length = Get<uint16_t>(head, 20);
    if (at + kVlrHeaderSize + length > h.point_offset) {
      return Status::Corruption(source.path() + ": " + what +
                                " runs past the start of the point data");
    }
    if (wanted(vlr)) {
      TB_ASSIGN_OR_RETURN(vlr.data, source.Read(at + kVlrHeaderSize, length, what));
    }
    vlrs.push_back(std::move(vlr));
    at += kVlrHeaderSize + length;
  }
  if (h.version_minor >= 4 && h.evlr_count > 0 && h.evlr_offset > 0) {
    at = h.evlr_offset;
    for (uint32_t i = 0; i < h.evlr_count; ++i) {
      const std::string what = "extended variable length record " + std::to_string(i);
      TB_ASSIGN_OR_RETURN(std::vector<char> head, source.Read(at, kEvlrHeaderSize, what));
      Vlr vlr{TrimmedString(head, 2, 16), Get<uint16_t>(head, 18), {}};
      const uint64_t length = Get<uint64_t>(head, 20);
      if (wanted(vlr)) {
        TB_ASSIGN_OR_RETURN(vlr.data, source.Read(at + kEvlrHeaderSize, length, what));
      }
      vlrs.push_back(std::move(vlr));
      at += kEvlrHeaderSize + length;
    }
  }
  return vlrs;
}

bool HasLaszipVlr(const std::vector<Vlr>& vlrs) {
  return std::any_of(vlrs.begin(), vlrs.end(), [](const Vlr& v) {
    return v.user_id == "laszip encoded" && v.record_id == kLaszipRecordId;
  });
}

// The EPSG code in a GeoKeyDirectory: ProjectedCSTypeGeoKey, else GeographicTypeGeoKey; nullopt
// when neither holds a registered code (32767 means "user-defined").
std::optional<int> GeoKeyEpsg(const std::vector<char>& data) {
  const size_t shorts = data.size() / 2;
  if (shorts < 4) return std::nullopt;
  const size_t keys = std::min<size_t>(Get<uint16_t>(data, 6), (shorts - 4) / 4);
  std::optional<int> projected, geographic;
  for (size_t k = 0; k < keys; ++k) {
    const size_t at = 8 + 8 * k;
    const uint16_t id = Get<uint16_t>(data, at);
    const uint16_t location = Get<uint16_t>(data, at + 2);
    const uint16_t value = Get<uint16_t>(data, at + 6);
    // Location 0: the value is the key's value itself, as both keys are SHORTs.
    if (location != 0 || value == 0 || value == kUserDefinedGeoKeyValue) continue;
    if (id == kProjectedCsTypeGeoKey) projected = value;
    if (id == kGeographicTypeGeoKey) geographic = value;
  }
  return projected ? projected : geographic;
}

Result<std::optional<Crs>> CrsFromVlrs(const std::string& path, const std::vector<Vlr>& vlrs) {
  for (const Vlr& v : vlrs) {
    if (v.user_id != "LASF_Projection" || v.record_id != kWktRecordId) continue;
    std::string wkt(v.data.begin(), v.data.end());
    wkt.erase(std::find(wkt.begin(), wkt.end(), '\0'), wkt.end());
    if (wkt.empty()) continue;
    auto crs = Crs::FromWkt(wkt);
    if (!crs.ok()) return crs.status().WithContext(path + ": OGC WKT record");
    return std::optional<Crs>(std::move(crs).value());
  }
  for (const Vlr& v : vlrs) {
    if (v.user_id != "LASF_Projection" || v.record_id != kGeoKeyDirectoryRecordId) continue;
    const std::optional<int> epsg = GeoKeyEpsg(v.data);
    if (!epsg) continue;
    auto crs = Crs::FromUserInput("EPSG:" + std::to_string(*epsg));
    if (!crs.ok()) return crs.status().WithContext(path + ": GeoKeyDirectory record");
    return std::optional<Crs>(std::move(crs).value());
  }
  return std::optional<Crs>();
}

Result<std::vector<CloudPoint>> ReadPoints(LasSource& source, const LasHeader& h) {
  std::vector<CloudPoint> points;
  points.reserve(h.point_count);
  // Formats 6-10 moved the return number to 4 bits and the class to its own byte.
  const bool extended = h.point_format >= 6;
  constexpr uint64_t kChunk = 65536;
  for (uint64_t first = 0; first < h.point_count; first += kChunk) {
    const uint64_t n = std::min(kChunk, h.point_count - first);
    TB_ASSIGN_OR_RETURN(std::vector<char> bytes,
                        source.Read(h.point_offset + first * h.record_length, n * h.record_length,
                                    "point records"));
    for (uint64_t i = 0; i < n; ++i) {
      const size_t at = i * h.record_length;
      CloudPoint p;
      p.x = Get<int32_t>(bytes, at) * h.scale[0] + h.offset[0];
      p.y = Get<int32_t>(bytes, at + 4) * h.scale[1] + h.offset[1];
      p.z = Get<int32_t>(bytes, at + 8) * h.scale[2] + h.offset[2];
      const uint8_t returns = Get<uint8_t>(bytes, at + 14);
      if (extended) {
        p.return_number = returns & 0x0F;
        p.classification = Get<uint8_t>(bytes, at + 16);
      } else {
        p.return_number = returns & 0x07;
        p.classification = Get<uint8_t>(bytes, at + 15) & 0x1F;
      }
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        return Status::Corruption(source.path() + ": point " + std::to_string(first + i) +
                                  ": coordinate is not finite after scaling");
      }
      points.push_back(p);
    }
  }
  return points;
}

bool HasLazExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".laz";
}

struct HeaderAndVlrs {
  LasHeader header;
  std::vector<Vlr> vlrs;
};

Result<HeaderAndVlrs> OpenHeaderAndVlrs(LasSource& source) {
  const uint64_t n = std::min<uint64_t>(source.size(), LasMinimumHeaderSize(4));
  TB_ASSIGN_OR_RETURN(std::vector<char> bytes, source.Read(0, n, "LAS header"));
  TB_ASSIGN_OR_RETURN(LasHeader header, DecodeHeader(source, bytes));
  TB_ASSIGN_OR_RETURN(std::vector<Vlr> vlrs, ReadVlrs(source, header));
  if (HasLaszipVlr(vlrs)) return Status::InvalidArgument(source.path() + " " + LazMessage());
  return HeaderAndVlrs{header, std::move(vlrs)};
}

}  // namespace

uint16_t LasMinimumHeaderSize(uint8_t minor) {
  if (minor >= 4) return 375;
  if (minor == 3) return 235;
  return 227;
}

uint16_t LasMinimumRecordLength(uint8_t format) {
  static constexpr uint16_t kLengths[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return kLengths[format];
}

Result<LasHeader> ReadLasHeader(const std::string& path) {
  if (HasLazExtension(path)) return Status::InvalidArgument(path + " " + LazMessage());
  TB_ASSIGN_OR_RETURN(LasSource source, LasSource::Open(path));
  TB_ASSIGN_OR_RETURN(HeaderAndVlrs opened, OpenHeaderAndVlrs(source));
  return opened.header;
}

Result<LasFile> ReadLas(const std::string& path) {
  if (HasLazExtension(path)) return Status::InvalidArgument(path + " " + LazMessage());
  TB_ASSIGN_OR_RETURN(LasSource source, LasSource::Open(path));
  TB_ASSIGN_OR_RETURN(HeaderAndVlrs opened, OpenHeaderAndVlrs(source));
  LasFile file;
  file.header = opened.header;
  TB_ASSIGN_OR_RETURN(file.cloud.crs, CrsFromVlrs(path, opened.vlrs));
  TB_ASSIGN_OR_RETURN(file.cloud.points, ReadPoints(source, file.header));
  return file;
}

}  // namespace tinbase
