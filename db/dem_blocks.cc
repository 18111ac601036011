// One block of a DEM in and out of `dem_blocks`: load and decode, encode and write, list a range
// of blocks, decode many at once, and the per-thread front cache in front of the process-wide
// block cache (db/dem_block_cache.h).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <span>

#include "core/raster/block_codec.h"
#include "db/dem_store.h"
#include "db/dem_store_impl.h"
#include "db/sql/each_row.h"

namespace tinbase {

using dem_internal::Quoted;

namespace {

// A stored block that does not decode is damaged, whatever the codec reported (an unknown codec
// number is InvalidArgument to the codec, but here the store wrote it): Corruption naming the
// block, so that no caller can take it for nodata or for the user's mistake.
Status DamagedBlock(const Status& decode, const DemInfo& dem, int level, int64_t bx, int64_t by) {
  return Status::Corruption("DEM " + Quoted(dem.name) + ", level " + std::to_string(level) +
                            " block (" + std::to_string(bx) + ", " + std::to_string(by) +
                            ") is damaged: " + decode.message());
}

// The blocks this thread used last, direct-mapped by block position (an 8 x 8 neighbourhood of
// blocks never collides), so a warm sample takes no lock, no SQL and no reference count. It holds
// at most kFrontBytes (and at least kMinFrontSlots blocks) per thread beyond the process-wide
// cache's limit.
struct FrontEntry {
  DemBlockKey key;
  DemBlockCache::Block block;
  bool used = false;
};
constexpr size_t kMaxFrontSlots = 64;
constexpr size_t kMinFrontSlots = 4;
constexpr size_t kFrontBytes = size_t{16} << 20;
thread_local std::array<FrontEntry, kMaxFrontSlots> t_front;

FrontEntry& FrontSlot(const DemBlockKey& key, int block_size) {
  const size_t block_bytes = static_cast<size_t>(block_size) * block_size * sizeof(float);
  const size_t slots =
      std::clamp(std::bit_floor(kFrontBytes / block_bytes), kMinFrontSlots, kMaxFrontSlots);
  const int side_bits = (std::countr_zero(slots) + 1) / 2;  // 8 x 8 for 64 slots
  const auto index = static_cast<size_t>(key.bx + (key.by << side_bits) + key.level * 7);
  return t_front[index & (slots - 1)];
}

}  // namespace

Result<DemStore::Impl::Block> DemStore::Impl::LoadBlock(const DemInfo& dem, int level, int64_t bx,
                                                        int64_t by) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT codec, data FROM dem_blocks "
                                        "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Block();
  }
  size_t size = 0;
  const uint8_t* data = stmt->ColumnBlob(1, &size);
  auto cells = DecodeBlock(static_cast<int>(stmt->ColumnInt(0)), std::span(data, size),
                           static_cast<size_t>(dem.block_size) * dem.block_size);
  stmt->Reset();
  if (!cells.ok()) return DamagedBlock(cells.status(), dem, level, bx, by);
  return Block(std::make_shared<const std::vector<float>>(std::move(cells).value()));
}

Result<const DemStore::Impl::Block*> DemStore::Impl::FrontBlock(const DemInfo& dem, int level,
                                                                int64_t bx, int64_t by) {
  if (token == 0) TB_RETURN_IF_ERROR(RefreshToken());
  const DemBlockKey key{token, dem.id, level, bx, by};
  FrontEntry& slot = FrontSlot(key, dem.block_size);
  if (slot.used && slot.key == key) return &slot.block;
  Block block;
  DemBlockCache& cache = DemBlockCache::Instance();
  if (!cache.Lookup(key, &block)) {
    TB_ASSIGN_OR_RETURN(block, LoadBlock(dem, level, bx, by));
    cache.Insert(key, block);
  }
  slot = FrontEntry{key, std::move(block), true};
  return &slot.block;
}

Status DemStore::Impl::WriteBlock(const DemInfo& dem, int level, int64_t bx, int64_t by,
                                  const std::vector<float>& cells, DemImportReport* report) {
  float zmin = std::numeric_limits<float>::infinity();
  float zmax = -zmin;
  for (float v : cells) {
    if (std::isnan(v)) continue;
    zmin = std::min(zmin, v);
    zmax = std::max(zmax, v);
  }
  if (zmin > zmax) {  // all nodata: not stored, a missing block reads as NaN
    TB_ASSIGN_OR_RETURN(Statement * del,
                        store.db().Cached("DELETE FROM dem_blocks "
                                          "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
    del->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
    TB_RETURN_IF_ERROR(del->Run());
    return AfterBlockWrite();
  }
  const std::vector<uint8_t> bytes = EncodeBlock(cells, dem.block_size);
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("INSERT INTO dem_blocks(dem, level, bx, by, codec, data, zmin, zmax) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?) "
                        "ON CONFLICT (dem, level, bx, by) DO UPDATE SET "
                        "codec = excluded.codec, data = excluded.data, "
                        "zmin = excluded.zmin, zmax = excluded.zmax"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, bx).Bind(4, by);
  stmt->Bind(5, static_cast<int64_t>(BlockCodec::kPlanarBloscZstd));
  stmt->BindBlob(6, bytes.data(), bytes.size());
  stmt->Bind(7, static_cast<double>(zmin)).Bind(8, static_cast<double>(zmax));
  TB_RETURN_IF_ERROR(stmt->Run());
  if (level == 0) {
    ++report->blocks_written;
    report->bytes_stored += static_cast<int64_t>(bytes.size());
  } else {
    ++report->overview_blocks_written;
  }
  return AfterBlockWrite();
}

Result<std::vector<DemStore::Impl::StoredBlock>> DemStore::Impl::ListBlocks(
    const DemInfo& dem, int level, int64_t bx_lo, int64_t bx_hi, int64_t by_lo, int64_t by_hi) {
  // The block extents alone, from the covering index dem_blocks_extent: reading a row's zmin
  // past its blob would walk every overflow page of the blob.
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT bx, by, zmin, zmax FROM dem_blocks "
                                        "WHERE dem = ? AND level = ? AND bx BETWEEN ? AND ? "
                                        "AND by BETWEEN ? AND ? ORDER BY by, bx"));
  stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level));
  stmt->Bind(3, bx_lo).Bind(4, bx_hi).Bind(5, by_lo).Bind(6, by_hi);
  std::vector<StoredBlock> out;
  // EachRow resets the statement before returning: callers read blocks, which may use it.
  TB_RETURN_IF_ERROR(EachRow(*stmt, [&](Statement& row) {
    out.push_back(StoredBlock{row.ColumnInt(0), row.ColumnInt(1),
                              static_cast<float>(row.ColumnDouble(2)),
                              static_cast<float>(row.ColumnDouble(3)), nullptr});
  }));
  return out;
}

Status DemStore::Impl::LoadCells(const DemInfo& dem, int level, std::span<StoredBlock> blocks) {
  if (token == 0) TB_RETURN_IF_ERROR(RefreshToken());
  DemBlockCache& cache = DemBlockCache::Instance();
  struct Miss {
    StoredBlock* block = nullptr;
    int codec = 0;
    std::vector<uint8_t> bytes;
    Status status;
  };
  std::vector<Miss> misses;
  for (StoredBlock& block : blocks) {
    const DemBlockKey key{token, dem.id, level, block.bx, block.by};
    if (cache.Lookup(key, &block.cells) && block.cells) continue;
    TB_ASSIGN_OR_RETURN(Statement * stmt,
                        store.db().Cached("SELECT codec, data FROM dem_blocks "
                                          "WHERE dem = ? AND level = ? AND bx = ? AND by = ?"));
    stmt->Bind(1, dem.id).Bind(2, static_cast<int64_t>(level)).Bind(3, block.bx).Bind(4, block.by);
    auto row = stmt->Step();
    Miss miss;
    miss.block = &block;
    if (row.ok() && *row) {
      size_t size = 0;
      const uint8_t* data = stmt->ColumnBlob(1, &size);
      miss.codec = static_cast<int>(stmt->ColumnInt(0));
      miss.bytes.assign(data, data + size);
    }
    stmt->Reset();
    TB_RETURN_IF_ERROR(row.status());
    if (!*row) return Status::Corruption("DEM " + Quoted(dem.name) + " block vanished");
    misses.push_back(std::move(miss));
  }
  const size_t cells = static_cast<size_t>(dem.block_size) * dem.block_size;
  // Decoding dominates a cold read: the blocks are decoded in parallel, each into its own
  // buffer, so the result does not depend on the thread count.
  tbb::parallel_for(size_t{0}, misses.size(), [&](size_t i) {
    auto out = std::make_shared<std::vector<float>>(cells);
    misses[i].status = DecodeBlockInto(misses[i].codec, misses[i].bytes, *out);
    misses[i].block->cells = std::move(out);
  });
  for (size_t i = 0; i < misses.size(); ++i) {
    StoredBlock& block = *misses[i].block;
    if (!misses[i].status.ok())
      return DamagedBlock(misses[i].status, dem, level, block.bx, block.by);
    cache.Insert(DemBlockKey{token, dem.id, level, block.bx, block.by}, block.cells);
  }
  return Status::Ok();
}

}  // namespace tinbase
