// Kernel: `serve` (the store as an HTTP service with the web viewer; service/http_server.h).
#include <pthread.h>

#include <csignal>
#include <fstream>
#include <iostream>
#include <thread>

#include "apps/tinbase/command.h"
#include "service/http_server.h"

namespace tinbase::cli {

namespace {

struct ServeArgs {
  std::string store;
  std::string listen = "127.0.0.1:8080";
  bool read_only = false;
  std::string token_file;
  int threads = 8;
  int max_body_mib = 16;
  std::string web_root = TINBASE_WEB_DIR;
};

// "host:port" (the port may be 0: any free port); InvalidArgument naming the text otherwise.
Status ParseListen(const std::string& text, service::ServiceOptions* options) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    return Status::InvalidArgument("--listen '" + text + "' is not host:port");
  const std::string port = text.substr(colon + 1);
  char* end = nullptr;
  const long value = std::strtol(port.c_str(), &end, 10);
  if (*end != '\0' || value < 0 || value > 65535)
    return Status::InvalidArgument("--listen '" + text + "': port '" + port +
                                   "' is not a number from 0 to 65535");
  options->host = text.substr(0, colon);
  options->port = static_cast<int>(value);
  return Status::Ok();
}

// The token is the file's first line, without surrounding white space.
Result<std::string> ReadToken(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status::IOError("--token-file '" + path + "' cannot be read");
  std::string token;
  std::getline(in, token);
  const size_t first = token.find_first_not_of(" \t\r");
  const size_t last = token.find_last_not_of(" \t\r");
  if (first == std::string::npos)
    return Status::InvalidArgument("--token-file '" + path + "': the first line is empty");
  return token.substr(first, last - first + 1);
}

Result<service::ServiceOptions> OptionsFrom(const ServeArgs& args) {
  service::ServiceOptions options;
  options.store_path = args.store;
  TB_RETURN_IF_ERROR(ParseListen(args.listen, &options));
  options.read_only = args.read_only;
  if (!args.token_file.empty()) {
    TB_ASSIGN_OR_RETURN(std::string token, ReadToken(args.token_file));
    options.token = token;
  }
  options.threads = args.threads;
  options.max_body_bytes = static_cast<size_t>(args.max_body_mib) << 20;
  options.web_root = args.web_root;
  return options;
}

int RunServe(const ServeArgs& args) {
  auto options = OptionsFrom(args);
  if (!options.ok()) return ReportError(options.status());
  // SIGINT and SIGTERM stop the server cleanly: a waiting thread takes them (signal handlers
  // could not safely stop it), so every thread started after this has them blocked.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  auto server = service::HttpServer::Start(*options);
  if (!server.ok()) return ReportError(server.status());
  std::thread stopper([&stop_signals, &server] {
    int signal = 0;
    sigwait(&stop_signals, &signal);
    (*server)->Stop();
  });
  std::cout << "serving " << args.store << " on http://" << options->host << ":"
            << (*server)->port() << "/" << (options->read_only ? " (read-only)" : "") << std::endl;
  const Status run = (*server)->Run();
  // Wake the stopper if the server ended by itself.
  pthread_kill(stopper.native_handle(), SIGTERM);
  stopper.join();
  if (!run.ok()) return ReportError(run);
  return kExitOk;
}

}  // namespace

void RegisterServeCommand(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* serve = app.add_subcommand("serve", "Serve the store over HTTP, with the web viewer");
  serve->add_option("store", args->store, "Store file")->required();
  serve->add_option("--listen", args->listen, "host:port to listen on (port 0: any free port)")
      ->capture_default_str();
  serve->add_flag("--read-only", args->read_only, "Refuse every write (403)");
  serve->add_option("--token-file", args->token_file,
                    "Writes need 'Authorization: Bearer <the file's first line>'");
  serve->add_option("--threads", args->threads, "Request threads")->capture_default_str();
  serve->add_option("--max-body-mib", args->max_body_mib, "Largest request body accepted (413)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  serve->add_option("--web-root", args->web_root, "The viewer's files")->capture_default_str();
  serve->callback([=] { *exit_code = RunServe(*args); });
}

}  // namespace tinbase::cli
