// Regression: a service stopped right after it started. cpp-httplib 0.11's Server::stop() does
// nothing until the accept loop runs, so a stop that came first was lost and Run() (and the
// thread joining it, or `tinbase serve` on an early SIGTERM) never returned.
#include <gtest/gtest.h>

#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

TEST(HttpServerStopTest, AStopRightAfterTheStartEndsTheService) {
  TempDir dir;
  service::ServiceOptions options;
  options.store_path = StoreTarget(dir, "s.tinbase");
  CopyDemoStore(options.store_path);
  for (int round = 0; round < 50; ++round) {
    TestService service(options);  // started on its thread, then stopped and joined at once
    ASSERT_TRUE(service.running());
  }
}

}  // namespace
}  // namespace tinbase::testing
