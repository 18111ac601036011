#include "db/sqlite/wal_write_batching.h"

#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <new>
#include <vector>

namespace tinbase {
namespace {

constexpr int kFrameHeaderBytes = 24;     // SQLite's WAL frame header (wal.c)
constexpr size_t kMaxGathered = 4 << 20;  // a spilling transaction writes its frames by this much

std::atomic<int64_t> requested_writes{0};
std::atomic<int64_t> issued_writes{0};

sqlite3_vfs* real_vfs = nullptr;

// A log file: the default VFS's file after our header, and the bytes gathered for it. A statement
// journal has the same layout and gathers nothing (`gathered` is null).
struct LogFile {
  sqlite3_file base;  // base.pMethods is kLogMethods (kStatementJournalMethods)
  sqlite3_file* real;
  std::vector<char>* gathered;
  sqlite3_int64 gathered_at;
  bool expect_page;  // the last write gathered a frame header, whose page comes next
};

LogFile* AsLog(sqlite3_file* f) { return reinterpret_cast<LogFile*>(f); }

int WriteThrough(LogFile* f, const void* data, int bytes, sqlite3_int64 offset) {
  issued_writes.fetch_add(1, std::memory_order_relaxed);
  return f->real->pMethods->xWrite(f->real, data, bytes, offset);
}

// The unix VFS writes at most 128 KiB - 1 bytes a call (it masks the length with 0x1ffff, as no
// page of SQLite's is larger), so what is gathered goes out in pieces of that size.
constexpr size_t kMaxWrite = 0x1ffff;

// `bytes` of `data` at `offset` in the default VFS's file, in pieces it writes whole.
int WriteInPieces(LogFile* f, const char* data, size_t bytes, sqlite3_int64 offset) {
  int rc = SQLITE_OK;
  for (size_t done = 0; done < bytes && rc == SQLITE_OK; done += kMaxWrite)
    rc = WriteThrough(f, data + done, static_cast<int>(std::min(kMaxWrite, bytes - done)),
                      offset + static_cast<sqlite3_int64>(done));
  return rc;
}

int Flush(LogFile* f) {
  if (f->gathered == nullptr) return SQLITE_OK;
  f->expect_page = false;
  const int rc = WriteInPieces(f, f->gathered->data(), f->gathered->size(), f->gathered_at);
  f->gathered->clear();
  return rc;
}

bool IsCommitFrameHeader(const void* data, int bytes) {
  if (bytes != kFrameHeaderBytes) return false;
  const auto* b = static_cast<const unsigned char*>(data);
  return (b[4] | b[5] | b[6] | b[7]) != 0;  // the database size after a commit, 0 otherwise
}

// False when memory ran out (no exception may cross SQLite's C frames).
bool Gather(LogFile* f, const void* data, int bytes, sqlite3_int64 offset) {
  try {
    if (f->gathered->empty()) f->gathered_at = offset;
    const char* p = static_cast<const char*>(data);
    f->gathered->insert(f->gathered->end(), p, p + bytes);
    return true;
  } catch (const std::bad_alloc&) {
    return false;
  }
}

// Frame headers and the pages after them gather while they follow one another; a commit frame's
// header goes out with everything before it, and its page straight after.
int LogWrite(sqlite3_file* file, const void* data, int bytes, sqlite3_int64 offset) {
  requested_writes.fetch_add(1, std::memory_order_relaxed);
  LogFile* f = AsLog(file);
  const bool follows =
      f->gathered->empty() ||
      offset == f->gathered_at + static_cast<sqlite3_int64>(f->gathered->size());
  const bool header = bytes == kFrameHeaderBytes;
  const bool page = f->expect_page && bytes != kFrameHeaderBytes;
  if (!follows || !(header || page) || !Gather(f, data, bytes, offset)) {
    if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
    return WriteThrough(f, data, bytes, offset);
  }
  f->expect_page = header;
  if (IsCommitFrameHeader(data, bytes) || f->gathered->size() >= kMaxGathered) return Flush(f);
  return SQLITE_OK;
}

int LogClose(sqlite3_file* file) {
  LogFile* f = AsLog(file);
  const int flushed = Flush(f);
  const int closed = f->real->pMethods ? f->real->pMethods->xClose(f->real) : SQLITE_OK;
  delete f->gathered;
  f->gathered = nullptr;
  return flushed != SQLITE_OK ? flushed : closed;
}

int LogRead(sqlite3_file* file, void* data, int bytes, sqlite3_int64 offset) {
  LogFile* f = AsLog(file);
  if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
  return f->real->pMethods->xRead(f->real, data, bytes, offset);
}

int LogTruncate(sqlite3_file* file, sqlite3_int64 size) {
  LogFile* f = AsLog(file);
  if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
  return f->real->pMethods->xTruncate(f->real, size);
}

int LogSync(sqlite3_file* file, int flags) {
  LogFile* f = AsLog(file);
  if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
  return f->real->pMethods->xSync(f->real, flags);
}

int LogFileSize(sqlite3_file* file, sqlite3_int64* size) {
  LogFile* f = AsLog(file);
  if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
  return f->real->pMethods->xFileSize(f->real, size);
}

int LogLock(sqlite3_file* file, int lock) {
  sqlite3_file* real = AsLog(file)->real;
  return real->pMethods->xLock(real, lock);
}

int LogUnlock(sqlite3_file* file, int lock) {
  sqlite3_file* real = AsLog(file)->real;
  return real->pMethods->xUnlock(real, lock);
}

int LogCheckReservedLock(sqlite3_file* file, int* out) {
  sqlite3_file* real = AsLog(file)->real;
  return real->pMethods->xCheckReservedLock(real, out);
}

int LogFileControl(sqlite3_file* file, int op, void* arg) {
  LogFile* f = AsLog(file);
  if (const int rc = Flush(f); rc != SQLITE_OK) return rc;
  return f->real->pMethods->xFileControl(f->real, op, arg);
}

int LogSectorSize(sqlite3_file* file) {
  sqlite3_file* real = AsLog(file)->real;
  return real->pMethods->xSectorSize(real);
}

int LogDeviceCharacteristics(sqlite3_file* file) {
  sqlite3_file* real = AsLog(file)->real;
  return real->pMethods->xDeviceCharacteristics(real);
}

// Version 1 methods: SQLite calls no shared-memory or memory-map method on a log file.
const sqlite3_io_methods kLogMethods = [] {
  sqlite3_io_methods m{};
  m.iVersion = 1;
  m.xClose = LogClose;
  m.xRead = LogRead;
  m.xWrite = LogWrite;
  m.xTruncate = LogTruncate;
  m.xSync = LogSync;
  m.xFileSize = LogFileSize;
  m.xLock = LogLock;
  m.xUnlock = LogUnlock;
  m.xCheckReservedLock = LogCheckReservedLock;
  m.xFileControl = LogFileControl;
  m.xSectorSize = LogSectorSize;
  m.xDeviceCharacteristics = LogDeviceCharacteristics;
  return m;
}();

// A statement journal that outgrew memory is written by SQLite one in-memory chunk a call, and a
// chunk is as large as SQLITE_CONFIG_STMTJRNL_SPILL (16 MiB: db/sqlite/sqlite_connection.cc), longer than
// the unix VFS writes in one call (it reports the rest as a full disk).
int StatementJournalWrite(sqlite3_file* file, const void* data, int bytes, sqlite3_int64 offset) {
  return WriteInPieces(AsLog(file), static_cast<const char*>(data), static_cast<size_t>(bytes),
                       offset);
}

const sqlite3_io_methods kStatementJournalMethods = [] {
  sqlite3_io_methods m = kLogMethods;
  m.xWrite = StatementJournalWrite;
  return m;
}();

int Open(sqlite3_vfs*, const char* name, sqlite3_file* file, int flags, int* out_flags) {
  // Everything but a log or a statement journal is the default VFS's own file, in the same
  // memory.
  const bool log = flags & SQLITE_OPEN_WAL, statement_journal = flags & SQLITE_OPEN_SUBJOURNAL;
  if (!log && !statement_journal) return real_vfs->xOpen(real_vfs, name, file, flags, out_flags);
  LogFile* f = AsLog(file);
  std::memset(f, 0, sizeof(LogFile));
  f->real = reinterpret_cast<sqlite3_file*>(reinterpret_cast<char*>(file) + sizeof(LogFile));
  const int rc = real_vfs->xOpen(real_vfs, name, f->real, flags, out_flags);
  if (rc != SQLITE_OK) {
    if (f->real->pMethods) f->real->pMethods->xClose(f->real);
    f->base.pMethods = nullptr;
    return rc;
  }
  if (statement_journal) {
    f->base.pMethods = &kStatementJournalMethods;
    return SQLITE_OK;
  }
  f->gathered = new (std::nothrow) std::vector<char>();
  if (f->gathered == nullptr) {
    f->real->pMethods->xClose(f->real);
    return SQLITE_NOMEM;
  }
  f->base.pMethods = &kLogMethods;
  return SQLITE_OK;
}

// The rest of the VFS is the default one's.
int Delete(sqlite3_vfs*, const char* name, int sync_dir) {
  return real_vfs->xDelete(real_vfs, name, sync_dir);
}
int Access(sqlite3_vfs*, const char* name, int flags, int* out) {
  return real_vfs->xAccess(real_vfs, name, flags, out);
}
int FullPathname(sqlite3_vfs*, const char* name, int n, char* out) {
  return real_vfs->xFullPathname(real_vfs, name, n, out);
}
void* DlOpen(sqlite3_vfs*, const char* name) { return real_vfs->xDlOpen(real_vfs, name); }
void DlError(sqlite3_vfs*, int n, char* out) { real_vfs->xDlError(real_vfs, n, out); }
void (*DlSym(sqlite3_vfs*, void* handle, const char* symbol))(void) {
  return real_vfs->xDlSym(real_vfs, handle, symbol);
}
void DlClose(sqlite3_vfs*, void* handle) { real_vfs->xDlClose(real_vfs, handle); }
int Randomness(sqlite3_vfs*, int n, char* out) { return real_vfs->xRandomness(real_vfs, n, out); }
int Sleep(sqlite3_vfs*, int microseconds) { return real_vfs->xSleep(real_vfs, microseconds); }
int CurrentTime(sqlite3_vfs*, double* out) { return real_vfs->xCurrentTime(real_vfs, out); }
int GetLastError(sqlite3_vfs*, int n, char* out) {
  return real_vfs->xGetLastError(real_vfs, n, out);
}
int CurrentTimeInt64(sqlite3_vfs*, sqlite3_int64* out) {
  return real_vfs->xCurrentTimeInt64(real_vfs, out);
}

constexpr const char* kName = "tinbase-wal-batching";

sqlite3_vfs* Register() {
  real_vfs = sqlite3_vfs_find(nullptr);
  if (real_vfs == nullptr || real_vfs->iVersion < 2) return nullptr;
  static sqlite3_vfs vfs;
  vfs.iVersion = 2;
  vfs.szOsFile = static_cast<int>(sizeof(LogFile)) + real_vfs->szOsFile;
  vfs.mxPathname = real_vfs->mxPathname;
  vfs.zName = kName;
  vfs.xOpen = Open;
  vfs.xDelete = Delete;
  vfs.xAccess = Access;
  vfs.xFullPathname = FullPathname;
  vfs.xDlOpen = DlOpen;
  vfs.xDlError = DlError;
  vfs.xDlSym = DlSym;
  vfs.xDlClose = DlClose;
  vfs.xRandomness = Randomness;
  vfs.xSleep = Sleep;
  vfs.xCurrentTime = CurrentTime;
  vfs.xGetLastError = GetLastError;
  vfs.xCurrentTimeInt64 = CurrentTimeInt64;
  if (sqlite3_vfs_register(&vfs, 0) != SQLITE_OK) return nullptr;
  return &vfs;
}

}  // namespace

const char* WalWriteBatchingVfs() {
  static sqlite3_vfs* vfs = Register();
  return vfs ? kName : nullptr;  // null: SQLite's default VFS, unbatched
}

WalWriteCounts WalWriteCountsSoFar() {
  return {requested_writes.load(std::memory_order_relaxed),
          issued_writes.load(std::memory_order_relaxed)};
}

}  // namespace tinbase
