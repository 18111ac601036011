// JSON answers and JSON errors. Every error the service sends, from a route or from the HTTP
// layer itself (404 of an unknown path, 413 of a large body), is a JSON object
// {"error": {"status": 400, "code": "invalid_argument", "message": "..."}} so clients parse one
// shape.
#pragma once

#include <httplib.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "core/base/status.h"

namespace tinbase::service {

// The HTTP status for a storage or input error: InvalidArgument 400, NotFound 404,
// Conflict 409, Busy 503, Corruption and IOError 500.
int HttpStatusFor(StatusCode code);

// Writes `body` as the answer, with Content-Type application/json.
void ReplyJson(httplib::Response& res, const nlohmann::json& body, int status = 200);
// As ReplyJson, unless the answer's text is longer than `max_bytes`: then 413 "result_too_large"
// naming its size and the limit (ServiceOptions::max_result_bytes).
void ReplyJsonWithin(httplib::Response& res, const nlohmann::json& body, size_t max_bytes,
                     const char* content_type = "application/json");
// The 413 "result_too_large" error for an answer of `bytes` (or more) over `max_bytes`.
void ReplyResultTooLarge(httplib::Response& res, size_t bytes, size_t max_bytes);
// Writes the JSON error for `status`; `code` is a short machine name ("bad_bbox").
void ReplyError(httplib::Response& res, int status, const std::string& code,
                const std::string& message);
// Writes the JSON error for a failed Status (HttpStatusFor its code).
void ReplyStatus(httplib::Response& res, const Status& status);

// The short machine name of an HTTP status used when a route gives none ("not_found", ...).
const char* ErrorCodeName(int http_status);

}  // namespace tinbase::service
