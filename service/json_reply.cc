// JSON answers and JSON errors.
#include "service/json_reply.h"

namespace tinbase::service {

int HttpStatusFor(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return 200;
    case StatusCode::kInvalidArgument:
      return 400;
    case StatusCode::kNotFound:
      return 404;
    case StatusCode::kConflict:
      return 409;
    case StatusCode::kBusy:
      return 503;
    case StatusCode::kCorruption:
    case StatusCode::kIOError:
      return 500;
  }
  return 500;
}

const char* ErrorCodeName(int http_status) {
  switch (http_status) {
    case 400:
      return "bad_request";
    case 401:
      return "unauthorized";
    case 403:
      return "forbidden";
    case 404:
      return "not_found";
    case 405:
      return "method_not_allowed";
    case 408:
      return "timeout";
    case 409:
      return "conflict";
    case 413:
      return "too_large";
    case 414:
      return "uri_too_long";
    case 415:
      return "unsupported_media_type";
    case 416:
      return "range_not_satisfiable";
    case 503:
      return "busy";
    default:
      return http_status >= 500 ? "internal" : "error";
  }
}

namespace {

// The error code of a Status in an answer: its StatusCodeName as one lower-case word.
const char* StatusCodeKey(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return "ok";
    case StatusCode::kNotFound:
      return "not_found";
    case StatusCode::kInvalidArgument:
      return "invalid_argument";
    case StatusCode::kCorruption:
      return "corruption";
    case StatusCode::kIOError:
      return "io_error";
    case StatusCode::kConflict:
      return "conflict";
    case StatusCode::kBusy:
      return "busy";
  }
  return "internal";
}

}  // namespace

void ReplyJson(httplib::Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void ReplyJsonWithin(httplib::Response& res, const nlohmann::json& body, size_t max_bytes,
                     const char* content_type) {
  std::string text = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (text.size() > max_bytes) return ReplyResultTooLarge(res, text.size(), max_bytes);
  res.status = 200;
  // set_content copies; a large answer is moved in instead.
  res.body = std::move(text);
  res.headers.erase("Content-Type");
  res.set_header("Content-Type", content_type);
}

void ReplyResultTooLarge(httplib::Response& res, size_t bytes, size_t max_bytes) {
  ReplyError(res, 413, "result_too_large",
             "the answer is " + std::to_string(bytes) +
                 " bytes, more than the service's result limit of " + std::to_string(max_bytes) +
                 " bytes (max_result_bytes); ask for a smaller bbox or selection");
}

void ReplyError(httplib::Response& res, int status, const std::string& code,
                const std::string& message) {
  nlohmann::json body = {{"error", {{"status", status}, {"code", code}, {"message", message}}}};
  // Messages may quote outside input; dump() replaces bytes that are not UTF-8 instead of
  // throwing, so a hostile byte never turns an error answer into a crash.
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

void ReplyStatus(httplib::Response& res, const Status& status) {
  ReplyError(res, HttpStatusFor(status.code()), StatusCodeKey(status.code()), status.message());
}

}  // namespace tinbase::service
