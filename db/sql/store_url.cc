// StoreUrl: the store target, parsed once.
#include "db/sql/store_url.h"

#include <vector>

namespace tinbase {

namespace {

bool StartsWith(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

bool IsPlainIdentifier(const std::string& name) {
  if (name.empty() || name.size() > 63) return false;
  if (!(name[0] == '_' || (name[0] >= 'a' && name[0] <= 'z'))) return false;
  for (char c : name)
    if (!(c == '_' || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return false;
  return true;
}

// "user:password@" becomes "user@" in what messages show.
std::string WithoutPassword(const std::string& url) {
  const size_t scheme = url.find("://");
  const size_t at = url.find('@', scheme + 3);
  const size_t slash = url.find('/', scheme + 3);
  if (at == std::string::npos || (slash != std::string::npos && slash < at)) return url;
  const size_t colon = url.find(':', scheme + 3);
  if (colon == std::string::npos || colon > at) return url;
  return url.substr(0, colon) + url.substr(at);
}

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return parts;
}

Result<StoreUrl> ParsePostgres(const std::string& target) {
  StoreUrl url;
  url.backend = Backend::kPostgres;
  url.pg_schema = "public";
  const size_t question = target.find('?');
  std::string base = target.substr(0, question);
  std::vector<std::string> kept;
  if (question != std::string::npos) {
    for (const std::string& pair : Split(target.substr(question + 1), '&')) {
      if (StartsWith(pair, "schema=")) {
        url.pg_schema = pair.substr(7);
        if (!IsPlainIdentifier(url.pg_schema))
          return Status::InvalidArgument(
              WithoutPassword(base) + ": schema '" + url.pg_schema +
              "' is not a plain lower-case name (letters a-z, digits and _, at most 63)");
      } else if (!pair.empty()) {
        kept.push_back(pair);
      }
    }
  }
  url.pg_conninfo = base;
  for (size_t i = 0; i < kept.size(); ++i) url.pg_conninfo += (i == 0 ? "?" : "&") + kept[i];
  url.label = WithoutPassword(base) + "?schema=" + url.pg_schema;
  return url;
}

}  // namespace

bool IsPostgresTarget(const std::string& target) {
  return StartsWith(target, "postgresql://") || StartsWith(target, "postgres://");
}

Result<StoreUrl> ParseStoreUrl(const std::string& target) {
  if (IsPostgresTarget(target)) return ParsePostgres(target);
  StoreUrl url;
  url.sqlite_path = StartsWith(target, "sqlite:") ? target.substr(7) : target;
  if (url.sqlite_path.empty())
    return Status::InvalidArgument("'" + target + "' names no store file");
  url.label = url.sqlite_path;
  return url;
}

}  // namespace tinbase
