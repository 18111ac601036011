#include "db/history/mesh_image.h"

#include <zstd.h>

#include <bit>
#include <cassert>
#include <string>

namespace tinbase {

namespace {

// Record layout (docs/format.md, "Mesh images"): magic, version, surface, digest, then the
// triangles, vertices and edges, each a count and its entries; integers little-endian.
constexpr uint32_t kMagic = 0x494d4254;  // "TBMI"
constexpr uint8_t kVersion = 1;
constexpr int kZstdLevel = 3;

class ByteWriter {
 public:
  void U8(uint8_t v) { out_.push_back(v); }
  void U64(uint64_t v) {
    for (int k = 0; k < 8; ++k) out_.push_back(static_cast<uint8_t>(v >> (8 * k)));
  }
  void I64(int64_t v) { U64(static_cast<uint64_t>(v)); }
  void F64(double v) { U64(std::bit_cast<uint64_t>(v)); }
  void OptI64(const std::optional<int64_t>& v) {
    U8(v ? 1 : 0);
    if (v) I64(*v);
  }
  std::vector<uint8_t>& bytes() { return out_; }

 private:
  std::vector<uint8_t> out_;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool ok() const { return ok_; }
  bool done() const { return pos_ == size_; }
  uint8_t U8() {
    if (!Need(1)) return 0;
    return data_[pos_++];
  }
  uint64_t U64() {
    if (!Need(8)) return 0;
    uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= static_cast<uint64_t>(data_[pos_++]) << (8 * k);
    return v;
  }
  int64_t I64() { return static_cast<int64_t>(U64()); }
  double F64() { return std::bit_cast<double>(U64()); }
  std::optional<int64_t> OptI64() {
    const uint8_t has = U8();
    if (has > 1) ok_ = false;
    return has == 1 ? std::optional<int64_t>(I64()) : std::nullopt;
  }
  // A count of entries each at least `min_bytes` long: bounded by what is left.
  uint64_t Count(size_t min_bytes) {
    const uint64_t n = U64();
    if (n > (size_ - pos_) / min_bytes) ok_ = false;
    return ok_ ? n : 0;
  }
  void Fail() { ok_ = false; }

 private:
  bool Need(size_t n) {
    if (!ok_ || size_ - pos_ < n) ok_ = false;
    return ok_;
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  bool ok_ = true;
};

void PutTriangle(ByteWriter& w, int64_t id, const std::optional<TriangleRow>& t) {
  w.I64(id);
  w.U8(t ? 1 : 0);
  if (!t) return;
  for (int64_t v : t->v) w.I64(v);
  for (const std::optional<int64_t>& n : t->n) w.OptI64(n);
  w.U8(t->visible ? 1 : 0);
  w.OptI64(t->tag);
  w.I64(t->block);
}

void PutVertex(ByteWriter& w, int64_t id, const std::optional<VertexRow>& v) {
  w.I64(id);
  w.U8(v ? 1 : 0);
  if (!v) return;
  w.F64(v->x);
  w.F64(v->y);
  w.F64(v->z);
  w.U8(static_cast<uint8_t>(v->kind));
}

void PutEdge(ByteWriter& w, const MeshEdge& e, const std::vector<EdgeConstraint>& rows) {
  w.I64(e.first);
  w.I64(e.second);
  w.U64(rows.size());
  for (const EdgeConstraint& c : rows) {
    w.OptI64(c.feature);
    w.U8(c.soft ? 1 : 0);
  }
}

void PutRows(ByteWriter& w, const MeshRowSet& rows) {
  w.U64(rows.triangles.size());
  for (const auto& [id, t] : rows.triangles) PutTriangle(w, id, t);
  w.U64(rows.vertices.size());
  for (const auto& [id, v] : rows.vertices) PutVertex(w, id, v);
  w.U64(rows.constraints.size());
  for (const auto& [e, c] : rows.constraints) PutEdge(w, e, c);
}

bool Flag(ByteReader& r) {
  const uint8_t v = r.U8();
  if (v > 1) r.Fail();
  return v == 1;
}

void GetRows(ByteReader& r, MeshRowSet* rows) {
  for (uint64_t n = r.Count(9); n > 0 && r.ok(); --n) {
    const int64_t id = r.I64();
    std::optional<TriangleRow> t;
    if (Flag(r)) {
      t.emplace();
      for (int64_t& v : t->v) v = r.I64();
      for (std::optional<int64_t>& m : t->n) m = r.OptI64();
      t->visible = Flag(r);
      t->tag = r.OptI64();
      t->block = r.I64();
    }
    rows->triangles.emplace(id, t);
  }
  for (uint64_t n = r.Count(9); n > 0 && r.ok(); --n) {
    const int64_t id = r.I64();
    std::optional<VertexRow> v;
    if (Flag(r)) {
      v.emplace();
      v->x = r.F64();
      v->y = r.F64();
      v->z = r.F64();
      const uint8_t kind = r.U8();
      if (kind > static_cast<uint8_t>(VertexKind::kUser)) r.Fail();
      v->kind = static_cast<VertexKind>(kind);
    }
    rows->vertices.emplace(id, v);
  }
  for (uint64_t n = r.Count(24); n > 0 && r.ok(); --n) {
    MeshEdge e;
    e.first = r.I64();
    e.second = r.I64();
    std::vector<EdgeConstraint>& list = rows->constraints[e];
    for (uint64_t k = r.Count(2); k > 0 && r.ok(); --k) {
      EdgeConstraint c;
      c.feature = r.OptI64();
      c.soft = Flag(r);
      list.push_back(c);
    }
  }
}

}  // namespace

void MeshRowSet::AddMissing(const MeshRowSet& other) {
  triangles.insert(other.triangles.begin(), other.triangles.end());
  vertices.insert(other.vertices.begin(), other.vertices.end());
  constraints.insert(other.constraints.begin(), other.constraints.end());
}

void MeshRowSet::Overwrite(const MeshRowSet& other) {
  for (const auto& [id, t] : other.triangles) triangles[id] = t;
  for (const auto& [id, v] : other.vertices) vertices[id] = v;
  for (const auto& [e, c] : other.constraints) constraints[e] = c;
}

MeshRowSet MeshRowSet::At(const MeshRowSet& keys) const {
  MeshRowSet out;
  for (const auto& [id, unused] : keys.triangles) {
    assert(triangles.count(id) > 0);
    out.triangles.emplace(id, triangles.at(id));
  }
  for (const auto& [id, unused] : keys.vertices) {
    assert(vertices.count(id) > 0);
    out.vertices.emplace(id, vertices.at(id));
  }
  for (const auto& [e, unused] : keys.constraints) {
    assert(constraints.count(e) > 0);
    out.constraints.emplace(e, constraints.at(e));
  }
  return out;
}

MeshRowSet MeshRowSet::DifferentFrom(const MeshRowSet& other) const {
  const auto same_vertex = [](const std::optional<VertexRow>& a,
                              const std::optional<VertexRow>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || (a->x == b->x && a->y == b->y && a->z == b->z && a->kind == b->kind);
  };
  MeshRowSet out;
  for (const auto& [id, t] : triangles)
    if (other.triangles.at(id) != t) out.triangles.emplace(id, t);
  for (const auto& [id, v] : vertices)
    if (!same_vertex(other.vertices.at(id), v)) out.vertices.emplace(id, v);
  for (const auto& [e, c] : constraints)
    if (other.constraints.at(e) != c) out.constraints.emplace(e, c);
  return out;
}

uint64_t Digest(const MeshRowSet& rows) {
  ByteWriter w;
  PutRows(w, rows);
  uint64_t h = 0xcbf29ce484222325ULL;
  for (uint8_t b : w.bytes()) {
    h ^= b;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::vector<uint8_t> EncodeMeshImage(const MeshImage& image) {
  ByteWriter w;
  w.U64(kMagic);
  w.U8(kVersion);
  w.I64(image.surface);
  w.U64(image.after_digest);
  PutRows(w, image.before);
  const std::vector<uint8_t>& raw = w.bytes();
  std::vector<uint8_t> out(8 + ZSTD_compressBound(raw.size()));
  // The raw size first, so that Decode knows what to allocate without trusting the frame.
  for (int k = 0; k < 8; ++k) out[k] = static_cast<uint8_t>(raw.size() >> (8 * k));
  const size_t n =
      ZSTD_compress(out.data() + 8, out.size() - 8, raw.data(), raw.size(), kZstdLevel);
  assert(!ZSTD_isError(n));
  out.resize(8 + n);
  return out;
}

Result<MeshImage> DecodeMeshImage(const uint8_t* data, size_t size, const std::string& what) {
  const auto bad = [&](const std::string& why) { return Status::Corruption(what + ": " + why); };
  if (size < 8) return bad("shorter than its header");
  uint64_t raw_size = 0;
  for (int k = 0; k < 8; ++k) raw_size |= static_cast<uint64_t>(data[k]) << (8 * k);
  const unsigned long long frame = ZSTD_getFrameContentSize(data + 8, size - 8);
  if (frame == ZSTD_CONTENTSIZE_ERROR || frame != raw_size)
    return bad("its zstd frame does not hold " + std::to_string(raw_size) + " bytes");
  std::vector<uint8_t> raw(raw_size);
  const size_t n = ZSTD_decompress(raw.data(), raw.size(), data + 8, size - 8);
  if (ZSTD_isError(n) || n != raw_size) return bad("its zstd frame does not decompress");
  ByteReader r(raw.data(), raw.size());
  MeshImage image;
  if (r.U64() != kMagic || r.U8() != kVersion) return bad("not a version 1 mesh image");
  image.surface = r.I64();
  image.after_digest = r.U64();
  GetRows(r, &image.before);
  if (!r.ok() || !r.done()) return bad("its record is truncated or malformed");
  return image;
}

}  // namespace tinbase
