// ServiceOptions: how `tinbase serve` runs (where it listens, who may write, what it accepts).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace tinbase::service {

struct ServiceOptions {
  std::string store_path;
  std::string host = "127.0.0.1";  // loopback unless told otherwise
  int port = 8080;                 // 0: any free port (tests)
  bool read_only = false;          // every write is refused with 403
  // When set, a write needs "Authorization: Bearer <token>".
  std::optional<std::string> token;
  int threads = 8;                              // request threads; one read connection each at most
  size_t max_body_bytes = size_t{16} << 20;     // larger request bodies get 413
  size_t max_result_bytes = size_t{256} << 20;  // larger answers get 413 naming the limit
  int read_timeout_seconds = 10;                // a client that sends nothing for this long is cut
  std::string web_root;                         // the viewer's files; empty: no viewer
};

}  // namespace tinbase::service
