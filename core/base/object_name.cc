#include "core/base/object_name.h"

#include <cstdint>
#include <cstdio>
#include <optional>

namespace tinbase {

namespace {

// The code point starting at name[*at] (advancing *at past it); nullopt for bytes that are not
// valid UTF-8 there.
std::optional<uint32_t> NextCodePoint(std::string_view name, size_t* at) {
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(name[i]); };
  const uint8_t lead = byte(*at);
  int length = 0;
  uint32_t cp = 0;
  uint32_t min = 0;
  if (lead < 0x80) {
    ++*at;
    return lead;
  } else if ((lead & 0xE0) == 0xC0) {
    length = 2, cp = lead & 0x1F, min = 0x80;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3, cp = lead & 0x0F, min = 0x800;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4, cp = lead & 0x07, min = 0x10000;
  } else {
    return std::nullopt;
  }
  if (*at + length > name.size()) return std::nullopt;
  for (int i = 1; i < length; ++i) {
    const uint8_t next = byte(*at + i);
    if ((next & 0xC0) != 0x80) return std::nullopt;
    cp = (cp << 6) | (next & 0x3F);
  }
  // Overlong forms, UTF-16 surrogates and values past Unicode are not UTF-8.
  if (cp < min || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return std::nullopt;
  *at += length;
  return cp;
}

bool IsControl(uint32_t cp) { return cp < 0x20 || (cp >= 0x7F && cp <= 0x9F); }

}  // namespace

std::string EscapedName(std::string_view name) {
  std::string out;
  for (const char c : name) {
    const auto b = static_cast<uint8_t>(c);
    if (b >= 0x20 && b < 0x7F && c != '\\') {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", b);
      out += hex;
    }
  }
  return out;
}

Status CheckObjectName(std::string_view kind, std::string_view name) {
  const auto bad = [&](const std::string& why) {
    return Status::InvalidArgument(std::string(kind) + " name '" + EscapedName(name) + "' " + why);
  };
  if (name.empty()) return Status::InvalidArgument(std::string(kind) + " name is empty");
  if (name.size() > kMaxObjectNameBytes)
    return bad("is longer than " + std::to_string(kMaxObjectNameBytes) + " bytes");
  if (name.front() == ' ' || name.back() == ' ') return bad("starts or ends with a space");
  for (size_t at = 0; at < name.size();) {
    const size_t start = at;
    const std::optional<uint32_t> cp = NextCodePoint(name, &at);
    if (!cp) return bad("is not valid UTF-8 at byte " + std::to_string(start + 1));
    if (IsControl(*cp)) return bad("has a control character at byte " + std::to_string(start + 1));
  }
  return Status::Ok();
}

}  // namespace tinbase
