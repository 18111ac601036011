// HttpServer: the limits, the JSON errors and the route groups on one cpp-httplib server.
#include "service/http_server.h"

#include <sys/socket.h>

#include <exception>
#include <memory>
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

// Debian's cpp-httplib listens with a backlog of 5. A burst of new connections overflows that
// queue; the kernel then drops their handshakes, a client's request arrives seconds late, and
// httplib closes the accepted connection unanswered when it outlasts the keep-alive wait. So the
// listening socket is remembered here and listen() is called again with the system's maximum,
// which Linux applies to a socket that is already listening.
struct ListeningSocket {
  socket_t fd = -1;
};

void RememberListeningSocket(httplib::Server& server,
                             const std::shared_ptr<ListeningSocket>& listening) {
  server.set_socket_options([listening](socket_t fd) {
    httplib::default_socket_options(fd);
    listening->fd = fd;
  });
}

Status WidenBacklog(const ListeningSocket& listening) {
  if (listening.fd < 0 || ::listen(listening.fd, SOMAXCONN) != 0)
    return Status::IOError("cannot widen the listening socket's backlog");
  return Status::Ok();
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
  auto listening = std::make_shared<ListeningSocket>();
  RememberListeningSocket(*server, listening);
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
  TB_RETURN_IF_ERROR(WidenBacklog(*listening));
  return std::unique_ptr<HttpServer>(new HttpServer(std::move(context), std::move(server), port));
}

Status HttpServer::Run() {
  // Paired with Stop(): of "Run started" and "stop requested", each side writes its own flag and
  // then reads the other's, so at least one of them sees the other's.
  run_started_ = true;
  if (stop_requested_) {
    run_returned_ = true;
    return Status::Ok();
  }
  const bool listened = server_->listen_after_bind();
  run_returned_ = true;
  if (!listened && !stop_requested_)
    return Status::IOError("the server stopped accepting connections");
  return Status::Ok();
}

void HttpServer::Stop() {
  stop_requested_ = true;
  context_->changes().Shutdown();
  // httplib's stop() does nothing until the accept loop runs; once Run() has begun, wait for it.
  if (run_started_) {
    while (!server_->is_running() && !run_returned_) std::this_thread::yield();
  }
  server_->stop();
}

}  // namespace tinbase::service
