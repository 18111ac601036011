// ServiceContext: the options, connections and notifier one service shares.
#include "service/service_context.h"

#include <utility>

#include "service/json_reply.h"

namespace tinbase::service {

namespace {

// Compares in time that depends only on the lengths, so an answer's timing tells nothing of how
// much of a guessed token was right.
bool SameToken(const std::string& given, const std::string& expected) {
  if (given.size() != expected.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < given.size(); ++i)
    difference |= static_cast<unsigned char>(given[i] ^ expected[i]);
  return difference == 0;
}

}  // namespace

ServiceContext::ServiceContext(ServiceOptions options, std::unique_ptr<StorePool> stores)
    : options_(std::move(options)), stores_(std::move(stores)) {}

Result<std::unique_ptr<ServiceContext>> ServiceContext::Open(const ServiceOptions& options) {
  TB_ASSIGN_OR_RETURN(auto stores,
                      StorePool::Open(options.store_path, options.read_only, options.threads));
  return std::unique_ptr<ServiceContext>(new ServiceContext(options, std::move(stores)));
}

bool ServiceContext::AllowWrite(const httplib::Request& req, httplib::Response& res) const {
  if (options_.read_only) {
    ReplyError(res, 403, "read_only", "the service runs --read-only: writes are refused");
    return false;
  }
  if (!options_.token) return true;
  const std::string header = req.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (header.empty()) {
    res.set_header("WWW-Authenticate", "Bearer");
    ReplyError(res, 401, "unauthorized", "a write needs an Authorization: Bearer token");
    return false;
  }
  const std::string given = header.rfind(prefix, 0) == 0 ? header.substr(prefix.size()) : "";
  if (!SameToken(given, *options_.token)) {
    res.set_header("WWW-Authenticate", "Bearer error=\"invalid_token\"");
    ReplyError(res, 401, "invalid_token", "the bearer token is wrong");
    return false;
  }
  return true;
}

}  // namespace tinbase::service
