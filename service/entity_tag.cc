// Entity tags from content, and If-None-Match.
#include "service/entity_tag.h"

#include <zlib.h>

#include <cstdio>

namespace tinbase::service {

namespace {

// The tag without W/ and quotes, as the weak comparison sees it.
std::string_view Opaque(std::string_view tag) {
  if (tag.substr(0, 2) == "W/") tag.remove_prefix(2);
  if (tag.size() >= 2 && tag.front() == '"' && tag.back() == '"')
    tag = tag.substr(1, tag.size() - 2);
  return tag;
}

}  // namespace

std::string EntityTag(std::string_view source, const std::string& variant) {
  // CRC-32 alone leaves one chance in 2^32 that a changed tile keeps its tag; the length makes
  // that smaller still for the edits that change a tile's size, which most do.
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(source.data()),
                          static_cast<uInt>(source.size()));
  char text[48];
  std::snprintf(text, sizeof text, "%08lx%zx", static_cast<unsigned long>(crc), source.size());
  std::string tag = "\"";
  tag += text;
  if (!variant.empty()) tag += "-" + variant;
  tag += "\"";
  return tag;
}

bool IfNoneMatchHits(const httplib::Request& req, const std::string& tag) {
  if (!req.has_header("If-None-Match")) return false;
  const std::string header = req.get_header_value("If-None-Match");
  const std::string_view want = Opaque(tag);
  // Entity tags hold no commas or spaces (RFC 9110's etagc), so the list splits plainly.
  size_t start = 0;
  while (start <= header.size()) {
    size_t end = header.find(',', start);
    if (end == std::string::npos) end = header.size();
    std::string_view item(header.data() + start, end - start);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item == "*" || (!item.empty() && Opaque(item) == want)) return true;
    start = end + 1;
  }
  return false;
}

bool ReplyNotModified(const httplib::Request& req, httplib::Response& res, const std::string& tag,
                      const char* cache_control) {
  res.set_header("ETag", tag);
  res.set_header("Cache-Control", cache_control);
  if (!IfNoneMatchHits(req, tag)) return false;
  res.status = 304;
  return true;
}

}  // namespace tinbase::service
