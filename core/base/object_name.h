// The names users give surfaces and DEMs: checked once, where a name is first stored, so that
// every later reader (`info --json`, GeoJSON properties, HTTP paths, a terminal) can print it.
//
// A name is 1 to 256 bytes of valid UTF-8 (no overlong forms, no surrogates) with no control
// character (U+0000-U+001F, U+007F-U+009F), so no newline or escape sequence, and it neither
// starts nor ends with a space. Thread-safe: pure functions.
#pragma once

#include <string>
#include <string_view>

#include "core/base/status.h"

namespace tinbase {

inline constexpr size_t kMaxObjectNameBytes = 256;

// Ok for a usable name; InvalidArgument "<kind> name <name, escaped>: <problem at byte N>".
// `kind` is "surface", "DEM", ...
Status CheckObjectName(std::string_view kind, std::string_view name);

// `name` with every byte outside printable ASCII written as \xHH, for messages about bad names.
std::string EscapedName(std::string_view name);

}  // namespace tinbase
