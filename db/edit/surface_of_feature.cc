#include "db/edit/surface_of_feature.h"

#include <string>

#include "db/sql/connection.h"

namespace tinbase {

Result<SurfaceInfo> SurfaceOfFeature(Store& store, int64_t id) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      store.db().Cached("SELECT surface FROM features WHERE id = ?"));
  stmt->Bind(1, id);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  if (!row) {
    stmt->Reset();
    return Status::NotFound("no feature " + std::to_string(id));
  }
  const int64_t surface = stmt->ColumnInt(0);
  stmt->Reset();
  return SurfaceStore(store).FindById(surface);
}

}  // namespace tinbase
