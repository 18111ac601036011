#include "db/history/as_of.h"

#include <string>

#include "db/history/revert.h"

namespace tinbase {

Result<std::unique_ptr<WriteTransaction>> BeginAsOf(Store& store, const SurfaceInfo& surface,
                                                    int64_t tx) {
  TB_ASSIGN_OR_RETURN(auto write, store.BeginWrite());
  TB_ASSIGN_OR_RETURN(RevertPlan plan, PlanAsOf(store, surface, tx));
  TB_ASSIGN_OR_RETURN(RevertReport report,
                      ApplyRevertPlan(store, plan, std::string("as of ") + std::to_string(tx)));
  (void)report;
  return write;
}

}  // namespace tinbase
