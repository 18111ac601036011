// HttpServer: `tinbase serve` itself. Builds the cpp-httplib server with the service's limits
// (body size, read timeout, thread pool), JSON errors for everything the HTTP layer refuses, and
// every route group of routes.h; then listens until Stop().
// Thread-safety: Stop() and port() may be called from any thread while Run() blocks in another.
#pragma once

#include <httplib.h>

#include <atomic>
#include <memory>

#include "core/base/status.h"
#include "service/service_context.h"
#include "service/service_options.h"

namespace tinbase::service {

class HttpServer {
 public:
  // Opens the store and binds the listening socket (port 0: any free port). Errors: the store's,
  // and IOError naming host and port when it cannot bind.
  static Result<std::unique_ptr<HttpServer>> Start(const ServiceOptions& options);
  ~HttpServer();

  // The bound port (the chosen one when options.port was 0).
  int port() const { return port_; }
  ServiceContext& context() { return *context_; }
  // Serves requests until Stop(). IOError when the accept loop fails.
  Status Run();
  void Stop();

 private:
  HttpServer(std::unique_ptr<ServiceContext> context, std::unique_ptr<httplib::Server> server,
             int port);
  std::unique_ptr<ServiceContext> context_;
  std::unique_ptr<httplib::Server> server_;
  int port_;
  // cpp-httplib's stop() does nothing before its accept loop runs; these let a Stop() that comes
  // before or while Run() starts still end it (see Stop()).
  std::atomic<bool> run_entered_{false};
  std::atomic<bool> run_done_{false};
  std::atomic<bool> stop_requested_{false};
};

}  // namespace tinbase::service
