// Reading a request's parameters, each checked once.
#include "service/request_params.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "db/query/surface_selection.h"

namespace tinbase::service {

namespace {

Status BadParam(const char* name, const std::string& text, const std::string& why) {
  return Status::InvalidArgument("parameter '" + std::string(name) + "': '" + text + "' " + why);
}

Result<double> ParseFinite(const char* name, const std::string& text) {
  if (text.empty()) return BadParam(name, text, "is empty");
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return BadParam(name, text, "is not a number");
  if (!std::isfinite(value) || errno == ERANGE)
    return BadParam(name, text, "is not a finite number");
  return value;
}

Result<int64_t> ParseInteger(const char* name, const std::string& text, int64_t min, int64_t max) {
  if (text.empty()) return BadParam(name, text, "is empty");
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (end != text.c_str() + text.size()) return BadParam(name, text, "is not a whole number");
  if (errno == ERANGE || value < min || value > max)
    return BadParam(name, text,
                    "is out of range (" + std::to_string(min) + " to " + std::to_string(max) + ")");
  return static_cast<int64_t>(value);
}

}  // namespace

std::optional<std::string> OptionalParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

Result<std::string> RequiredParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name))
    return Status::InvalidArgument("missing parameter '" + std::string(name) + "'");
  return req.get_param_value(name);
}

Result<double> FiniteParam(const httplib::Request& req, const char* name) {
  TB_ASSIGN_OR_RETURN(std::string text, RequiredParam(req, name));
  return ParseFinite(name, text);
}

Result<int64_t> IntegerParam(const httplib::Request& req, const char* name, int64_t min,
                             int64_t max, std::optional<int64_t> fallback) {
  if (!req.has_param(name)) {
    if (fallback) return *fallback;
    return Status::InvalidArgument("missing parameter '" + std::string(name) + "'");
  }
  return ParseInteger(name, req.get_param_value(name), min, max);
}

Result<std::optional<Box>> BboxParam(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::optional<Box>();
  auto box = ParseBbox(req.get_param_value(name));
  if (!box.ok()) return box.status().WithContext("parameter '" + std::string(name) + "'");
  return std::optional<Box>(*box);
}

Result<int64_t> IntegerPathPart(const httplib::Request& req, size_t index, const char* what,
                                int64_t min, int64_t max) {
  if (index >= req.matches.size())
    return Status::InvalidArgument("the path has no " + std::string(what));
  return ParseInteger(what, req.matches[index].str(), min, max);
}

Result<SurfaceInfo> SurfaceFromPath(Store& store, const httplib::Request& req, size_t index) {
  if (index >= req.matches.size()) return Status::InvalidArgument("the path names no surface");
  return SurfaceStore(store).Find(req.matches[index].str());
}

}  // namespace tinbase::service
