// Gzip for answers the HTTP layer does not compress itself. cpp-httplib compresses only text-like
// content types (JSON, text/*), but Cesium expects terrain tiles gzipped when the browser accepts
// it, and a browser's own Accept-Encoding decides. Thread-safety: pure functions.
#pragma once

#include <httplib.h>

#include <string>
#include <string_view>

#include "core/base/status.h"

namespace tinbase::service {

// `bytes` as one gzip member (RFC 1952), at zlib's default level. IOError when zlib fails (it
// does only when out of memory).
Result<std::string> Gzip(std::string_view bytes);

// Whether the request's Accept-Encoding allows gzip: "gzip" (or "x-gzip") or "*" with a q-value
// above 0, and gzip not refused by name with q=0. No header: false (identity is always allowed).
bool AcceptsGzip(const httplib::Request& req);

}  // namespace tinbase::service
