// HttpServer: the limits, the JSON errors and the route groups on one cpp-httplib server.
#include "service/http_server.h"

#include <exception>
#include <thread>
#include <utility>

#include "service/json_reply.h"
#include "service/routes.h"

namespace tinbase::service {

namespace {

// The HTTP layer answers some requests itself (no route matched, a body over the limit, a
// malformed request line); give those the same JSON error shape as the routes' own errors.
void ReplyJsonForBareErrors(httplib::Server& server) {
  server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a route already wrote its JSON error
    std::string message;
    switch (res.status) {
      case 404:
        message = "no route for " + req.method + " " + req.path;
        break;
      case 413:
        message = "the request body is larger than the service accepts";
        break;
      default:
        message = "the request was refused (HTTP " + std::to_string(res.status) + ")";
    }
    ReplyError(res, res.status, ErrorCodeName(res.status), message);
  });
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr error) {
        std::string what = "unknown exception";
        try {
          std::rethrow_exception(std::move(error));
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        ReplyError(res, 500, "internal", "internal error: " + what);
      });
}

void ApplyLimits(httplib::Server& server, const ServiceOptions& options) {
  server.set_payload_max_length(options.max_body_bytes);
  server.set_read_timeout(options.read_timeout_seconds, 0);
  server.set_write_timeout(options.read_timeout_seconds, 0);
  server.set_keep_alive_max_count(1000);
  // httplib writes an answer's headers and body in separate sends; with Nagle's algorithm the
  // body then waits for the client's delayed ACK of the headers on every keep-alive request.
  server.set_tcp_nodelay(true);
  const size_t threads = static_cast<size_t>(options.threads);
  server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
}

}  // namespace

HttpServer::HttpServer(std::unique_ptr<ServiceContext> context,
                       std::unique_ptr<httplib::Server> server, int port)
    : context_(std::move(context)), server_(std::move(server)), port_(port) {}

HttpServer::~HttpServer() { Stop(); }

Result<std::unique_ptr<HttpServer>> HttpServer::Start(const ServiceOptions& options) {
  if (options.threads < 1 || options.threads > 1024)
    return Status::InvalidArgument("--threads must be 1 to 1024, got " +
                                   std::to_string(options.threads));
  TB_ASSIGN_OR_RETURN(auto context, ServiceContext::Open(options));
  auto server = std::make_unique<httplib::Server>();
  ApplyLimits(*server, options);
  ReplyJsonForBareErrors(*server);
  RegisterSurfaceRoutes(*server, *context);
  RegisterTileRoutes(*server, *context);
  RegisterDemRoutes(*server, *context);
  RegisterEditRoutes(*server, *context);
  RegisterChangeRoutes(*server, *context);
  RegisterViewerRoutes(*server, *context);
  int port = options.port;
  if (port == 0) {
    port = server->bind_to_any_port(options.host);
    if (port < 0) return Status::IOError("cannot listen on " + options.host + " (any port)");
  } else if (!server->bind_to_port(options.host, port)) {
    return Status::IOError("cannot listen on " + options.host + ":" + std::to_string(port) +
                           " (in use, or not an address of this machine)");
  }
  return std::unique_ptr<HttpServer>(new HttpServer(std::move(context), std::move(server), port));
}

Status HttpServer::Run() {
  run_entered_ = true;
  const bool listened = stop_requested_ || server_->listen_after_bind();
  run_done_ = true;
  if (!listened) return Status::IOError("the server stopped accepting connections");
  return Status::Ok();
}

void HttpServer::Stop() {
  context_->changes().Shutdown();
  // Either Run() sees the request and does not start, or Stop() sees Run() entered and waits for
  // its accept loop (or its failure) so that stop() is not lost (both flags are seq_cst).
  stop_requested_ = true;
  if (run_entered_) {
    while (!server_->is_running() && !run_done_) std::this_thread::yield();
  }
  server_->stop();
}

}  // namespace tinbase::service
