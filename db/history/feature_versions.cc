#include "db/history/feature_versions.h"

#include <utility>

#include "core/tin/feature_mode.h"
#include "core/vector/feature_wkb.h"
#include "core/vector/line_z_wkb.h"
#include "core/vector/point_wkb.h"
#include "db/sql/each_row.h"

namespace tinbase {

namespace {

constexpr const char* kVersionColumns =
    "v.feature, v.tx, v.surface, v.present, v.mode, t.value, v.level, v.attributes, v.geometry, "
    "c.action, c.time, v.name, v.z_from FROM feature_versions v LEFT JOIN tags t ON t.id = v.tag "
    "LEFT JOIN changes c ON c.tx = v.tx ";

FeatureVersion VersionOfRow(const Statement& stmt) {
  FeatureVersion v;
  v.feature = stmt.ColumnInt(0);
  v.tx = stmt.ColumnInt(1);
  v.surface = stmt.ColumnInt(2);
  v.present = stmt.ColumnInt(3) != 0;
  v.mode = stmt.ColumnText(4);
  if (!stmt.ColumnIsNull(5)) v.tag = stmt.ColumnText(5);
  if (!stmt.ColumnIsNull(6)) v.level = stmt.ColumnDouble(6);
  v.attributes = stmt.ColumnText(7);
  size_t size = 0;
  const uint8_t* blob = stmt.ColumnBlob(8, &size);
  v.geometry.assign(blob, blob + size);
  if (!stmt.ColumnIsNull(9)) v.action = stmt.ColumnText(9);
  if (!stmt.ColumnIsNull(10)) v.time = stmt.ColumnText(10);
  if (!stmt.ColumnIsNull(11)) v.name = stmt.ColumnText(11);
  v.z_from = stmt.ColumnText(12);
  return v;
}

// The versions `stmt` selects (kVersionColumns), its parameters bound.
Result<std::vector<FeatureVersion>> ReadVersions(Statement& stmt) {
  std::vector<FeatureVersion> out;
  TB_RETURN_IF_ERROR(
      EachRow(stmt, [&](const Statement& row) { out.push_back(VersionOfRow(row)); }));
  return out;
}

// The ids (column 0) `stmt` selects, its parameters bound.
Result<std::vector<int64_t>> ReadIds(Statement& stmt) {
  std::vector<int64_t> out;
  TB_RETURN_IF_ERROR(EachRow(stmt, [&](const Statement& row) { out.push_back(row.ColumnInt(0)); }));
  return out;
}

Result<bool> HasVersions(Store& store, int64_t feature) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("SELECT 1 FROM feature_versions WHERE feature = ? LIMIT 1"));
  stmt->Bind(1, feature);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  stmt->Reset();
  return row;
}

// One past the largest feature id any row or version names; with concurrent writers the next of
// the features' sequence, which is past all of them (migration 0017).
Result<int64_t> FreshFeatureId(Store& store) {
  if (!store.db().NumbersRowsByLargestId()) return store.db().ReserveIds("features", 1);
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT max(m) FROM (SELECT max(id) AS m FROM features "
                                        "UNION ALL SELECT max(feature) FROM feature_versions) u"));
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  const int64_t largest = row && !stmt->ColumnIsNull(0) ? stmt->ColumnInt(0) : 0;
  stmt->Reset();
  return largest + 1;
}

Status CopyRow(Store& store, int64_t tx, int64_t feature, bool present) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("INSERT INTO feature_versions(feature, tx, surface, present, name, mode, "
                        "level, tag, attributes, geometry, min_x, min_y, max_x, max_y, z_from) "
                        "SELECT id, ?, surface, ?, name, mode, level, tag, attributes, geometry, "
                        "min_x, min_y, max_x, max_y, z_from FROM features WHERE id = ?"));
  stmt->Bind(1, tx).Bind(2, int64_t{present ? 1 : 0}).Bind(3, feature);
  return stmt->Run();
}

}  // namespace

Status SettleFeatureId(Store& store, int64_t wanted, EditorFeature& f) {
  int64_t id = wanted;
  if (id == 0) {
    TB_ASSIGN_OR_RETURN(const bool reused, HasVersions(store, f.id));
    if (!reused) return Status::Ok();
    TB_ASSIGN_OR_RETURN(id, FreshFeatureId(store));
  }
  if (id == f.id) return Status::Ok();
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("UPDATE features SET id = ? WHERE id = ?"));
  stmt->Bind(1, id).Bind(2, f.id);
  TB_RETURN_IF_ERROR(stmt->Run());
  f.id = id;
  return Status::Ok();
}

Status RecordFeatureVersions(Store& store, int64_t tx, const std::vector<int64_t>& written,
                             const std::vector<int64_t>& removed) {
  for (int64_t id : written) TB_RETURN_IF_ERROR(CopyRow(store, tx, id, /*present=*/true));
  for (int64_t id : removed) TB_RETURN_IF_ERROR(CopyRow(store, tx, id, /*present=*/false));
  return Status::Ok();
}

Result<std::vector<FeatureVersion>> VersionsOfFeature(Store& store, int64_t feature) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached(std::string("SELECT ") + kVersionColumns +
                                                          "WHERE v.feature = ? ORDER BY v.tx"));
  stmt->Bind(1, feature);
  return ReadVersions(*stmt);
}

Result<std::map<int64_t, std::vector<int64_t>>> FeaturesTouchedSince(Store& store, int64_t since) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT tx, feature FROM feature_versions WHERE tx > ? "
                                        "ORDER BY tx, feature"));
  stmt->Bind(1, since);
  std::map<int64_t, std::vector<int64_t>> out;
  TB_RETURN_IF_ERROR(EachRow(
      *stmt, [&](const Statement& row) { out[row.ColumnInt(0)].push_back(row.ColumnInt(1)); }));
  return out;
}

Result<std::vector<int64_t>> FeaturesTouchedBy(Store& store, int64_t tx) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("SELECT feature FROM feature_versions WHERE tx = ? ORDER BY feature"));
  stmt->Bind(1, tx);
  return ReadIds(*stmt);
}

Result<std::optional<FeatureVersion>> VersionAt(Store& store, int64_t feature, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, store.db().Cached(std::string("SELECT ") + kVersionColumns +
                                                          "WHERE v.feature = ? AND v.tx <= ? "
                                                          "ORDER BY v.tx DESC LIMIT 1"));
  stmt->Bind(1, feature).Bind(2, tx);
  TB_ASSIGN_OR_RETURN(std::vector<FeatureVersion> one, ReadVersions(*stmt));
  if (one.empty()) return std::optional<FeatureVersion>();
  return std::optional<FeatureVersion>(std::move(one.front()));
}

Result<std::vector<int64_t>> LaterVersions(Store& store, int64_t feature, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT tx FROM feature_versions WHERE feature = ? "
                                        "AND tx > ? ORDER BY tx"));
  stmt->Bind(1, feature).Bind(2, tx);
  return ReadIds(*stmt);
}

Result<std::vector<int64_t>> FeaturesChangedAfter(Store& store, int64_t surface, int64_t tx) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT DISTINCT feature FROM feature_versions "
                                        "WHERE surface = ? AND tx > ? ORDER BY feature"));
  stmt->Bind(1, surface).Bind(2, tx);
  return ReadIds(*stmt);
}

Result<EditorFeature> EditorFeatureOf(const FeatureVersion& version) {
  EditorFeature f;
  f.id = version.feature;
  // WriteFeature stores the tag, else the label, as the name: the label brings the name back.
  f.label = version.name.empty() ? std::string("feature ") + std::to_string(version.feature)
                                 : version.name;
  auto mode = ParseFeatureMode(version.mode);
  if (!mode.ok())
    return Status::InvalidArgument(std::string("feature ") + std::to_string(version.feature) +
                                   ": " + mode.status().message());
  f.mode = *mode;
  f.tag = version.tag;
  f.level = version.level;
  f.attributes = nlohmann::json::parse(version.attributes, nullptr, /*allow_exceptions=*/false);
  if (f.attributes.is_discarded()) f.attributes = nlohmann::json::object();
  auto z_from = ParseZFrom(version.z_from);
  if (!z_from.ok()) return Status::Corruption(f.label + ": " + z_from.status().message());
  f.z_from = *z_from;
  if (f.mode == FeatureMode::kPoints) {
    auto points = PointsFromWkb(version.geometry);
    if (!points.ok()) return Status::Corruption(f.label + ": " + points.status().message());
    f.points = std::move(*points);
  } else if (IsLineMode(f.mode) && f.z_from == ZFrom::kFeature) {
    TB_RETURN_IF_ERROR(LinesZFromWkb(version.geometry, &f.lines, &f.line_z).WithContext(f.label));
  } else if (IsLineMode(f.mode)) {
    auto lines = LinesFromWkb(version.geometry);
    if (!lines.ok()) return Status::Corruption(f.label + ": " + lines.status().message());
    f.lines = std::move(*lines);
  } else {
    auto polygons = PolygonsFromWkb(version.geometry);
    if (!polygons.ok()) return Status::Corruption(f.label + ": " + polygons.status().message());
    f.polygons = std::move(*polygons);
  }
  return f;
}

}  // namespace tinbase
