#include "db/integrity_lines.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "db/sql/each_row.h"

namespace tinbase {

Result<std::vector<LineProblem>> CheckConstraintKinds(Store& store, const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("SELECT c.va, c.vb, coalesce(c.feature, 0), c.kind, coalesce(f.mode, '') "
                        "FROM constraints c LEFT JOIN features f ON f.id = c.feature "
                        "WHERE c.surface = ? AND c.kind <> CASE WHEN f.mode = 'softline' "
                        "THEN 'soft' ELSE 'hard' END ORDER BY c.va, c.vb, 3"));
  stmt->Bind(1, surface.id);
  std::vector<LineProblem> out;
  TB_RETURN_IF_ERROR(EachRow(*stmt, [&](Statement& row) {
    const int64_t feature = row.ColumnInt(2);
    const std::string mode = row.ColumnText(4);
    const std::string owner = feature == 0 ? "it has no feature"
                                           : "feature " + std::to_string(feature) + " is a " +
                                                 (mode.empty() ? "missing feature" : mode);
    out.push_back({"constraint-kind", "constraint (" + std::to_string(row.ColumnInt(0)) + ", " +
                                          std::to_string(row.ColumnInt(1)) + ") is kind '" +
                                          row.ColumnText(3) + "' but " + owner});
  }));
  return out;
}

Result<std::vector<LineProblem>> CheckLineZ(Store& store, const SurfaceInfo& surface,
                                            const LineElevation& lines) {
  // The z is computed from the same plan position by the same rule as when it was written, so
  // only round-off of an equal computation is allowed for.
  constexpr double kSlack = 1e-9;
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("SELECT v.id, v.x, v.y, v.z, c.feature FROM constraints c "
                        "JOIN features f ON f.id = c.feature JOIN vertices v ON v.id = c.va "
                        "WHERE c.surface = ?1 AND f.z_from = 'feature' UNION ALL "
                        "SELECT v.id, v.x, v.y, v.z, c.feature FROM constraints c "
                        "JOIN features f ON f.id = c.feature JOIN vertices v ON v.id = c.vb "
                        "WHERE c.surface = ?1 AND f.z_from = 'feature' ORDER BY 1, 5"));
  stmt->Bind(1, surface.id);
  std::map<int64_t, std::string> found;  // by vertex id, the first constraint's finding
  TB_RETURN_IF_ERROR(EachRow(*stmt, [&](Statement& row) {
    const int64_t id = row.ColumnInt(0);
    if (found.count(id)) return;
    const Point2 p{row.ColumnDouble(1), row.ColumnDouble(2)};
    const double z = row.ColumnDouble(3);
    const std::optional<double> expected = lines.ZAt(p);
    if (expected && std::fabs(*expected - z) <= kSlack * std::max(1.0, std::fabs(z))) return;
    char text[240];
    if (expected)
      std::snprintf(text, sizeof text,
                    "vertex %lld at %s on 3D line feature %lld has z %.17g but "
                    "the lines give %.17g",
                    static_cast<long long>(id), FormatPoint(p).c_str(),
                    static_cast<long long>(row.ColumnInt(4)), z, *expected);
    else
      std::snprintf(text, sizeof text,
                    "vertex %lld at %s of 3D line feature %lld lies on no 3D "
                    "line",
                    static_cast<long long>(id), FormatPoint(p).c_str(),
                    static_cast<long long>(row.ColumnInt(4)));
    found.emplace(id, text);
  }));
  std::vector<LineProblem> out;
  for (const auto& [id, text] : found) out.push_back({"line-z", text});
  return out;
}

}  // namespace tinbase
