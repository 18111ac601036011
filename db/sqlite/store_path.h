// StorePathProblem: what stands between a path and opening it as a store, found before SQLite
// tries, so that the user reads the real cause ("is a directory", "permission denied", "the
// directory is not writable") rather than the "unable to open database file" or "disk I/O
// error" SQLite reports for all of them. Never throws (std::filesystem's throwing calls are not
// used: a path too long or in an unreadable directory is an answer, not an exception).
// Thread-safe.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/sql/connection.h"

namespace tinbase {

// Ok when `path` can be opened in `mode` as far as the file system tells: for kCreate nothing
// exists there and its directory is writable; otherwise a regular file is there that this
// process may read (kReadOnly) or read and write (kReadWrite), in a directory where the `-wal`
// and `-shm` files beside it can be created (for kReadWrite always; for kReadOnly only when they
// do not exist yet). NotFound for no file; InvalidArgument naming the path and the cause else.
Status StorePathProblem(const std::string& path, Connection::Mode mode);

// Words for the operating system's error `errnum` as it concerns a store: "no space left on
// the device", "permission denied", ...; empty for 0.
std::string DescribeSystemError(int errnum);

}  // namespace tinbase
