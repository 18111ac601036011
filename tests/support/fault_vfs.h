// FaultVfs: an SQLite VFS for tests that fails the Nth I/O of a store's files, so a test can loop
// N over every read, write, sync and file creation of a command and demand that each run ends in
// success or a clean error with the store holding all or none of each transaction
// (docs/reliability.md, "Fault injection under SQLite").
//
// The shim wraps the default ("unix") VFS. While a ScopedFaultVfs lives it is SQLite's default,
// so every connection opened meanwhile (the store's writer, its WAL checkpointer, a reader) goes
// through it without the code under test knowing. Only the files whose path begins with the
// plan's prefix, and SQLite's nameless temporary files, are counted and failed: PROJ's proj.db
// and GDAL's files are left alone. Its files offer no memory map (their methods are version 2),
// so every page read is an xRead the shim sees.
//
// A fault is one of the errors a real disk gives: SQLITE_IOERR (EIO), SQLITE_FULL (ENOSPC), or a
// short write (part of the buffer written, then SQLITE_FULL, as the unix VFS reports one); a
// file creation that fails is SQLITE_CANTOPEN. It fires once (transient) or on the Nth and every
// later operation of the planned kinds (persistent: a disk that stays full).
// Thread-safety: the counters are atomic, as the checkpointer's thread does I/O too. One
// ScopedFaultVfs at a time.
#pragma once

#include <cstdint>
#include <string>

namespace tinbase::testing {

enum FaultKind : unsigned {
  kFaultRead = 1,
  kFaultWrite = 2,  // xWrite and xTruncate
  kFaultSync = 4,
  kFaultOpen = 8,  // xOpen of a file (creation of the -wal, -shm, temporary files)
  kFaultAll = 15,
};

enum class FaultError { kIoError, kFull, kShortWrite };

struct FaultPlan {
  std::string path_prefix;  // files counted: those whose path begins with it, and temp files
  unsigned kinds = kFaultAll;
  int64_t fail_at = 0;  // the 1-based index of the operation that fails; 0: none fails
  FaultError error = FaultError::kIoError;
  bool persistent = false;  // every operation from fail_at on fails, not only the one
};

const char* FaultErrorName(FaultError error);

class ScopedFaultVfs {
 public:
  // Makes the shim SQLite's default VFS, counting from zero under `plan`.
  explicit ScopedFaultVfs(FaultPlan plan);
  // Stops failing and makes the unix VFS the default again. Connections opened meanwhile keep
  // the shim, which then only passes their calls through.
  ~ScopedFaultVfs();
  ScopedFaultVfs(const ScopedFaultVfs&) = delete;
  ScopedFaultVfs& operator=(const ScopedFaultVfs&) = delete;

  // Operations of the planned kinds on the planned files so far.
  int64_t operations() const;
  // Whether a fault was injected.
  bool fired() const;
  // Stops failing (the disk has room again); counting goes on.
  void Disarm();
};

}  // namespace tinbase::testing
