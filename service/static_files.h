// Static files of the web viewer: a request path mapped into one directory and never outside it,
// and the content type a browser needs for each kind of file. Stateless; safe from any thread.
#pragma once

#include <filesystem>
#include <string>

#include "core/base/status.h"

namespace tinbase::service {

// The regular file that `relative` (a '/'-separated path from a URL, already percent-decoded)
// names under `root`. Every segment must be a plain name (letters, digits, '_', '-', '.', '@',
// '+'; not starting with '.'), so "..", hidden files and odd bytes are InvalidArgument naming
// the segment. A file that is missing, not regular, or (through a symbolic link) outside the
// canonical `root` is NotFound.
Result<std::filesystem::path> ResolveStaticPath(const std::filesystem::path& root,
                                                const std::string& relative);

// The Content-Type for a file by its extension ("text/javascript" for .js and .mjs, ...);
// "application/octet-stream" when the extension is unknown.
const char* StaticContentType(const std::filesystem::path& file);

}  // namespace tinbase::service
