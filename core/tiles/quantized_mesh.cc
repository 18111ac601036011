// QuantizedMesh: see quantized_mesh.h. The layout is Cesium's quantized-mesh-1.0 specification.
#include "core/tiles/quantized_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace tinbase {

namespace {

constexpr uint8_t kExtensionNormals = 1;
constexpr uint8_t kExtensionWaterMask = 2;
constexpr uint8_t kExtensionMetadata = 4;
constexpr size_t kWaterMaskCells = 256 * 256;
// Above this vertex count indices take four bytes instead of two (the specification's 64 * 1024).
constexpr size_t kMaxShortIndexVertices = 65536;

uint16_t ZigZag(int32_t n) { return static_cast<uint16_t>((n << 1) ^ (n >> 31)); }
int32_t UnZigZag(uint16_t n) { return static_cast<int32_t>(n >> 1) ^ -static_cast<int32_t>(n & 1); }

class ByteWriter {
 public:
  template <typename T>
  void Put(T value) {
    uint8_t raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));  // the machine is little-endian, as the format
    bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
  }
  void PutIndex(uint32_t value, bool wide) {
    if (wide) {
      Put<uint32_t>(value);
    } else {
      Put<uint16_t>(static_cast<uint16_t>(value));
    }
  }
  void Align(size_t to) {
    while (bytes_.size() % to != 0) bytes_.push_back(0);
  }
  void PutBytes(const void* data, size_t n) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + n);
  }
  std::vector<uint8_t> Take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

class ByteReader {
 public:
  ByteReader(const std::vector<uint8_t>& bytes, const std::string& source)
      : bytes_(bytes), source_(source) {}

  size_t offset() const { return offset_; }
  size_t left() const { return bytes_.size() - offset_; }
  bool done() const { return offset_ >= bytes_.size(); }

  template <typename T>
  Status Get(const char* what, T* value) {
    TB_RETURN_IF_ERROR(Need(what, sizeof(T)));
    std::memcpy(value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return Status::Ok();
  }
  Status GetIndex(const char* what, bool wide, uint32_t* value) {
    if (wide) return Get(what, value);
    uint16_t narrow = 0;
    TB_RETURN_IF_ERROR(Get(what, &narrow));
    *value = narrow;
    return Status::Ok();
  }
  // A count of `size`-byte items, checked against the bytes left before anything is allocated.
  Status GetCount(const char* what, size_t size, uint32_t* count) {
    TB_RETURN_IF_ERROR(Get(what, count));
    if (static_cast<uint64_t>(*count) * size > left())
      return Error(std::string(what) + " says " + std::to_string(*count) + " items of " +
                   std::to_string(size) + " bytes, but only " + std::to_string(left()) +
                   " bytes are left");
    return Status::Ok();
  }
  Status Skip(const char* what, size_t n) {
    TB_RETURN_IF_ERROR(Need(what, n));
    offset_ += n;
    return Status::Ok();
  }
  Status Align(size_t to) {
    const size_t pad = (to - offset_ % to) % to;
    return Skip("index padding", pad);
  }
  const uint8_t* here() const { return bytes_.data() + offset_; }
  Status Error(const std::string& message) const {
    return Status::InvalidArgument(source_ + ": " + message + " (at byte " +
                                   std::to_string(offset_) + ")");
  }

 private:
  Status Need(const char* what, size_t n) const {
    if (n > left())
      return Error(std::string("truncated in ") + what + ": " + std::to_string(n) +
                   " bytes needed, " + std::to_string(left()) + " left");
    return Status::Ok();
  }

  const std::vector<uint8_t>& bytes_;
  const std::string& source_;
  size_t offset_ = 0;
};

Status CheckShape(const QuantizedMesh& mesh) {
  const size_t n = mesh.vertex_count();
  if (mesh.v.size() != n || mesh.height.size() != n)
    return Status::InvalidArgument("quantized mesh: u, v and height differ in length");
  for (size_t i = 0; i < n; ++i)
    if (mesh.u[i] > kQuantizedMax || mesh.v[i] > kQuantizedMax || mesh.height[i] > kQuantizedMax)
      return Status::InvalidArgument("quantized mesh: vertex " + std::to_string(i) +
                                     " is outside 0..32767");
  if (mesh.triangles.size() % 3 != 0)
    return Status::InvalidArgument("quantized mesh: triangle indices not a multiple of 3");
  uint32_t highest = 0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const uint32_t index = mesh.triangles[i];
    if (index >= n || index > highest)
      return Status::InvalidArgument("quantized mesh: triangle index " + std::to_string(i) + " (" +
                                     std::to_string(index) +
                                     ") is out of range or not in first-use order");
    if (index == highest) ++highest;
  }
  for (const auto* edge : {&mesh.west, &mesh.south, &mesh.east, &mesh.north})
    for (uint32_t index : *edge)
      if (index >= n)
        return Status::InvalidArgument("quantized mesh: edge vertex " + std::to_string(index) +
                                       " is out of range");
  if (mesh.normals && mesh.normals->size() != 2 * n)
    return Status::InvalidArgument("quantized mesh: normals need two bytes per vertex");
  if (mesh.water_mask && mesh.water_mask->size() != 1 && mesh.water_mask->size() != kWaterMaskCells)
    return Status::InvalidArgument("quantized mesh: a water mask is 1 or 65536 bytes");
  return Status::Ok();
}

void PutExtension(ByteWriter& out, uint8_t id, const void* data, size_t size) {
  out.Put<uint8_t>(id);
  out.Put<uint32_t>(static_cast<uint32_t>(size));
  out.PutBytes(data, size);
}

void PutHeader(ByteWriter& out, const QuantizedMeshHeader& h) {
  for (double d : {h.center_x, h.center_y, h.center_z}) out.Put(d);
  out.Put(h.min_height);
  out.Put(h.max_height);
  for (double d :
       {h.sphere_x, h.sphere_y, h.sphere_z, h.sphere_radius, h.horizon_x, h.horizon_y, h.horizon_z})
    out.Put(d);
}

Status GetHeader(ByteReader& in, QuantizedMeshHeader* h) {
  for (double* d : {&h->center_x, &h->center_y, &h->center_z})
    TB_RETURN_IF_ERROR(in.Get("header", d));
  TB_RETURN_IF_ERROR(in.Get("header", &h->min_height));
  TB_RETURN_IF_ERROR(in.Get("header", &h->max_height));
  for (double* d : {&h->sphere_x, &h->sphere_y, &h->sphere_z, &h->sphere_radius, &h->horizon_x,
                    &h->horizon_y, &h->horizon_z})
    TB_RETURN_IF_ERROR(in.Get("header", d));
  return Status::Ok();
}

Status GetZigZagColumn(ByteReader& in, const char* what, size_t n, std::vector<uint16_t>* column) {
  column->resize(n);
  int32_t value = 0;
  for (size_t i = 0; i < n; ++i) {
    uint16_t code = 0;
    TB_RETURN_IF_ERROR(in.Get(what, &code));
    value += UnZigZag(code);
    if (value < 0 || value > kQuantizedMax)
      return in.Error(std::string(what) + " of vertex " + std::to_string(i) + " decodes to " +
                      std::to_string(value) + ", outside 0..32767");
    (*column)[i] = static_cast<uint16_t>(value);
  }
  return Status::Ok();
}

Status GetTriangles(ByteReader& in, bool wide, size_t vertices, std::vector<uint32_t>* out) {
  TB_RETURN_IF_ERROR(in.Align(wide ? 4 : 2));
  uint32_t count = 0;
  TB_RETURN_IF_ERROR(in.GetCount("triangle count", 3 * (wide ? 4 : 2), &count));
  out->resize(static_cast<size_t>(count) * 3);
  uint32_t highest = 0;
  for (uint32_t& index : *out) {
    uint32_t code = 0;
    TB_RETURN_IF_ERROR(in.GetIndex("triangle indices", wide, &code));
    if (code > highest)
      return in.Error("triangle index code " + std::to_string(code) +
                      " is above the high-water mark");
    index = highest - code;
    if (code == 0) ++highest;
    if (index >= vertices)
      return in.Error("triangle index " + std::to_string(index) + " is not a vertex");
  }
  return Status::Ok();
}

Status GetEdge(ByteReader& in, const char* what, bool wide, size_t vertices,
               std::vector<uint32_t>* out) {
  uint32_t count = 0;
  TB_RETURN_IF_ERROR(in.GetCount(what, wide ? 4 : 2, &count));
  out->resize(count);
  for (uint32_t& index : *out) {
    TB_RETURN_IF_ERROR(in.GetIndex(what, wide, &index));
    if (index >= vertices)
      return in.Error(std::string(what) + " vertex " + std::to_string(index) + " is not a vertex");
  }
  return Status::Ok();
}

Status GetExtensions(ByteReader& in, QuantizedMesh* mesh) {
  while (!in.done()) {
    uint8_t id = 0;
    uint32_t length = 0;
    TB_RETURN_IF_ERROR(in.Get("extension id", &id));
    TB_RETURN_IF_ERROR(in.GetCount("extension length", 1, &length));
    const uint8_t* data = in.here();
    if (id == kExtensionNormals) {
      if (length != 2 * mesh->vertex_count())
        return in.Error("the normals extension has " + std::to_string(length) + " bytes for " +
                        std::to_string(mesh->vertex_count()) + " vertices");
      mesh->normals.emplace(data, data + length);
    } else if (id == kExtensionWaterMask) {
      if (length != 1 && length != kWaterMaskCells)
        return in.Error("a water mask has 1 or 65536 bytes, not " + std::to_string(length));
      mesh->water_mask.emplace(data, data + length);
    } else if (id == kExtensionMetadata) {
      uint32_t json = 0;
      if (length < 4) return in.Error("the metadata extension is shorter than its length field");
      std::memcpy(&json, data, 4);
      if (json != length - 4)
        return in.Error("the metadata extension's JSON length " + std::to_string(json) +
                        " does not fit its " + std::to_string(length) + " bytes");
      mesh->metadata.emplace(reinterpret_cast<const char*>(data + 4), json);
    }
    TB_RETURN_IF_ERROR(in.Skip("extension", length));
  }
  return Status::Ok();
}

int8_t SignNotZero(double v) { return v < 0 ? -1 : 1; }

uint8_t ToUnorm8(double v) {
  return static_cast<uint8_t>(std::lround((std::clamp(v, -1.0, 1.0) * 0.5 + 0.5) * 255.0));
}

double FromUnorm8(uint8_t v) { return std::clamp(v / 255.0 * 2.0 - 1.0, -1.0, 1.0); }

}  // namespace

Result<std::vector<uint8_t>> EncodeQuantizedMesh(const QuantizedMesh& mesh) {
  TB_RETURN_IF_ERROR(CheckShape(mesh));
  const size_t n = mesh.vertex_count();
  const bool wide = n > kMaxShortIndexVertices;
  ByteWriter out;
  PutHeader(out, mesh.header);
  out.Put<uint32_t>(static_cast<uint32_t>(n));
  for (const auto* column : {&mesh.u, &mesh.v, &mesh.height}) {
    int32_t previous = 0;
    for (uint16_t value : *column) {
      out.Put(ZigZag(static_cast<int32_t>(value) - previous));
      previous = value;
    }
  }
  out.Align(wide ? 4 : 2);
  out.Put<uint32_t>(static_cast<uint32_t>(mesh.triangles.size() / 3));
  uint32_t highest = 0;
  for (uint32_t index : mesh.triangles) {
    out.PutIndex(highest - index, wide);
    if (index == highest) ++highest;
  }
  for (const auto* edge : {&mesh.west, &mesh.south, &mesh.east, &mesh.north}) {
    out.Put<uint32_t>(static_cast<uint32_t>(edge->size()));
    for (uint32_t index : *edge) out.PutIndex(index, wide);
  }
  if (mesh.normals)
    PutExtension(out, kExtensionNormals, mesh.normals->data(), mesh.normals->size());
  if (mesh.water_mask)
    PutExtension(out, kExtensionWaterMask, mesh.water_mask->data(), mesh.water_mask->size());
  if (mesh.metadata) {
    std::vector<uint8_t> data(4 + mesh.metadata->size());
    const auto json = static_cast<uint32_t>(mesh.metadata->size());
    std::memcpy(data.data(), &json, 4);
    std::memcpy(data.data() + 4, mesh.metadata->data(), mesh.metadata->size());
    PutExtension(out, kExtensionMetadata, data.data(), data.size());
  }
  return out.Take();
}

Result<QuantizedMesh> DecodeQuantizedMesh(const std::vector<uint8_t>& bytes,
                                          const std::string& source) {
  if (bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b)
    return Status::InvalidArgument(source + ": the tile is gzipped; gunzip it first");
  ByteReader in(bytes, source);
  QuantizedMesh mesh;
  TB_RETURN_IF_ERROR(GetHeader(in, &mesh.header));
  uint32_t n = 0;
  TB_RETURN_IF_ERROR(in.GetCount("vertex count", 6, &n));
  TB_RETURN_IF_ERROR(GetZigZagColumn(in, "u", n, &mesh.u));
  TB_RETURN_IF_ERROR(GetZigZagColumn(in, "v", n, &mesh.v));
  TB_RETURN_IF_ERROR(GetZigZagColumn(in, "height", n, &mesh.height));
  const bool wide = n > kMaxShortIndexVertices;
  TB_RETURN_IF_ERROR(GetTriangles(in, wide, n, &mesh.triangles));
  TB_RETURN_IF_ERROR(GetEdge(in, "west edge", wide, n, &mesh.west));
  TB_RETURN_IF_ERROR(GetEdge(in, "south edge", wide, n, &mesh.south));
  TB_RETURN_IF_ERROR(GetEdge(in, "east edge", wide, n, &mesh.east));
  TB_RETURN_IF_ERROR(GetEdge(in, "north edge", wide, n, &mesh.north));
  TB_RETURN_IF_ERROR(GetExtensions(in, &mesh));
  return mesh;
}

void OrderVerticesByFirstUse(QuantizedMesh& mesh) {
  const size_t n = mesh.vertex_count();
  constexpr uint32_t kUnset = UINT32_MAX;
  std::vector<uint32_t> new_index(n, kUnset);
  uint32_t next = 0;
  for (uint32_t index : mesh.triangles)
    if (new_index[index] == kUnset) new_index[index] = next++;
  for (uint32_t& index : new_index)
    if (index == kUnset) index = next++;
  const auto permute = [&](auto& column, size_t width) {
    auto old = column;
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < width; ++k) column[new_index[i] * width + k] = old[i * width + k];
  };
  permute(mesh.u, 1);
  permute(mesh.v, 1);
  permute(mesh.height, 1);
  if (mesh.normals) permute(*mesh.normals, 2);
  for (uint32_t& index : mesh.triangles) index = new_index[index];
  for (auto* edge : {&mesh.west, &mesh.south, &mesh.east, &mesh.north})
    for (uint32_t& index : *edge) index = new_index[index];
}

void OctEncodeNormal(double x, double y, double z, uint8_t* out) {
  const double l1 = std::abs(x) + std::abs(y) + std::abs(z);
  double px = x / l1;
  double py = y / l1;
  if (z < 0) {
    const double ox = px;
    px = (1 - std::abs(py)) * SignNotZero(ox);
    py = (1 - std::abs(ox)) * SignNotZero(py);
  }
  out[0] = ToUnorm8(px);
  out[1] = ToUnorm8(py);
}

void OctDecodeNormal(const uint8_t* in, double* x, double* y, double* z) {
  double px = FromUnorm8(in[0]);
  double py = FromUnorm8(in[1]);
  double pz = 1 - (std::abs(px) + std::abs(py));
  if (pz < 0) {
    const double ox = px;
    px = (1 - std::abs(py)) * SignNotZero(ox);
    py = (1 - std::abs(ox)) * SignNotZero(py);
  }
  const double length = std::sqrt(px * px + py * py + pz * pz);
  *x = px / length;
  *y = py / length;
  *z = pz / length;
}

}  // namespace tinbase
