// ServiceContext: what every route of one running service shares: its options, its connections
// to the store, the notifier of committed edits, and the surfaces' summaries.
// Thread-safety: every member may be called from any thread.
#pragma once

#include <httplib.h>

#include <memory>

#include "core/base/status.h"
#include "service/change_notifier.h"
#include "service/service_options.h"
#include "service/store_pool.h"
#include "service/surface_summary_cache.h"

namespace tinbase::service {

class ServiceContext {
 public:
  static Result<std::unique_ptr<ServiceContext>> Open(const ServiceOptions& options);

  const ServiceOptions& options() const { return options_; }
  StorePool& stores() { return *stores_; }
  ChangeNotifier& changes() { return changes_; }
  SurfaceSummaryCache& summaries() { return summaries_; }

  // Whether `req` may write: false after answering 403 when the service is read-only, or 401
  // when a token is required and the request's "Authorization: Bearer" does not carry it.
  bool AllowWrite(const httplib::Request& req, httplib::Response& res) const;

 private:
  ServiceContext(ServiceOptions options, std::unique_ptr<StorePool> stores);
  ServiceOptions options_;
  std::unique_ptr<StorePool> stores_;
  ChangeNotifier changes_;
  SurfaceSummaryCache summaries_;
};

}  // namespace tinbase::service
