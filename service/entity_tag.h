// Entity tags (RFC 9110, section 8.8.3) for answers that clients cache: a tag made from the bytes
// an answer is derived from, so it changes exactly when they change (an edit that rewrites a tile
// gives the tile a new tag; an edit elsewhere leaves it alone), and the If-None-Match check that
// turns a repeated request into 304 Not Modified without building the answer again.
// Thread-safety: pure functions.
#pragma once

#include <httplib.h>

#include <string>
#include <string_view>

namespace tinbase::service {

// A strong tag, quoted: zlib's CRC-32 and the length of `source`, then `variant` (which says how
// the answer was made from the source: the extensions kept, the content coding), so two
// representations of one source never share a tag.
std::string EntityTag(std::string_view source, const std::string& variant);

// Whether the request's If-None-Match names `tag` (by weak comparison, as RFC 9110 asks for
// If-None-Match) or is "*".
bool IfNoneMatchHits(const httplib::Request& req, const std::string& tag);

// Sets ETag and Cache-Control; when If-None-Match names the tag, also answers 304 with no body
// and returns true (the caller stops there).
bool ReplyNotModified(const httplib::Request& req, httplib::Response& res, const std::string& tag,
                      const char* cache_control);

// Answers that may change with any edit: a cache keeps them but asks again each time, and the
// entity tag makes that cheap (304).
inline constexpr const char* kRevalidate = "no-cache";

}  // namespace tinbase::service
