#include "tests/support/fault_vfs.h"

#include <sqlite3.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <utility>

namespace tinbase::testing {
namespace {

// One shim for the process: connections keep a pointer to it after the scope that made it the
// default ends, so it lives as long as the process.
struct FaultState {
  sqlite3_vfs* real = nullptr;
  FaultPlan plan;
  std::atomic<int64_t> count{0};
  std::atomic<bool> armed{false};
  std::atomic<bool> fired{false};
};
FaultState g_state;
sqlite3_vfs g_vfs;
sqlite3_io_methods g_methods;

// The errno of the fault this thread injected last, for xGetLastError (what the message of
// StatusFromSqlite quotes).
thread_local int g_injected_errno = 0;

struct FaultFile {
  sqlite3_file base;
  bool counted;
  sqlite3_file* real;  // the unix VFS's file, allocated right after this struct
};

sqlite3_file* Real(sqlite3_file* file) { return reinterpret_cast<FaultFile*>(file)->real; }
bool Counted(sqlite3_file* file) { return reinterpret_cast<FaultFile*>(file)->counted; }

// Counts one operation of `kind`; true when it must fail.
bool Tick(unsigned kind) {
  if ((g_state.plan.kinds & kind) == 0) return false;
  const int64_t n = ++g_state.count;
  if (!g_state.armed.load()) return false;
  const int64_t at = g_state.plan.fail_at;
  const bool fail = at > 0 && (n == at || (g_state.plan.persistent && n > at));
  if (!fail) return false;
  g_state.fired = true;
  g_injected_errno = g_state.plan.error == FaultError::kIoError ? EIO : ENOSPC;
  return true;
}

int WriteError() {
  return g_state.plan.error == FaultError::kIoError ? SQLITE_IOERR_WRITE : SQLITE_FULL;
}

int Close(sqlite3_file* file) { return Real(file)->pMethods->xClose(Real(file)); }

int Read(sqlite3_file* file, void* buffer, int amount, sqlite3_int64 offset) {
  if (Counted(file) && Tick(kFaultRead)) return SQLITE_IOERR_READ;
  return Real(file)->pMethods->xRead(Real(file), buffer, amount, offset);
}

int Write(sqlite3_file* file, const void* buffer, int amount, sqlite3_int64 offset) {
  if (Counted(file) && Tick(kFaultWrite)) {
    if (g_state.plan.error == FaultError::kShortWrite && amount > 1)
      (void)Real(file)->pMethods->xWrite(Real(file), buffer, amount / 2, offset);
    return WriteError();
  }
  return Real(file)->pMethods->xWrite(Real(file), buffer, amount, offset);
}

int Truncate(sqlite3_file* file, sqlite3_int64 size) {
  if (Counted(file) && Tick(kFaultWrite))
    return g_state.plan.error == FaultError::kIoError ? SQLITE_IOERR_TRUNCATE : SQLITE_FULL;
  return Real(file)->pMethods->xTruncate(Real(file), size);
}

int Sync(sqlite3_file* file, int flags) {
  if (Counted(file) && Tick(kFaultSync)) return SQLITE_IOERR_FSYNC;
  return Real(file)->pMethods->xSync(Real(file), flags);
}

int FileSize(sqlite3_file* file, sqlite3_int64* size) {
  return Real(file)->pMethods->xFileSize(Real(file), size);
}
int Lock(sqlite3_file* file, int level) { return Real(file)->pMethods->xLock(Real(file), level); }
int Unlock(sqlite3_file* file, int level) {
  return Real(file)->pMethods->xUnlock(Real(file), level);
}
int CheckReservedLock(sqlite3_file* file, int* out) {
  return Real(file)->pMethods->xCheckReservedLock(Real(file), out);
}
int FileControl(sqlite3_file* file, int op, void* arg) {
  return Real(file)->pMethods->xFileControl(Real(file), op, arg);
}
int SectorSize(sqlite3_file* file) { return Real(file)->pMethods->xSectorSize(Real(file)); }
int DeviceCharacteristics(sqlite3_file* file) {
  return Real(file)->pMethods->xDeviceCharacteristics(Real(file));
}
int ShmMap(sqlite3_file* file, int region, int size, int extend, void volatile** out) {
  return Real(file)->pMethods->xShmMap(Real(file), region, size, extend, out);
}
int ShmLock(sqlite3_file* file, int offset, int n, int flags) {
  return Real(file)->pMethods->xShmLock(Real(file), offset, n, flags);
}
void ShmBarrier(sqlite3_file* file) { Real(file)->pMethods->xShmBarrier(Real(file)); }
int ShmUnmap(sqlite3_file* file, int delete_flag) {
  return Real(file)->pMethods->xShmUnmap(Real(file), delete_flag);
}

bool PlannedPath(const char* name) {
  if (name == nullptr) return true;  // a temporary file (statement journal, sorter)
  const std::string& prefix = g_state.plan.path_prefix;
  return !prefix.empty() && std::strncmp(name, prefix.c_str(), prefix.size()) == 0;
}

int Open(sqlite3_vfs*, const char* name, sqlite3_file* file, int flags, int* out_flags) {
  auto* f = reinterpret_cast<FaultFile*>(file);
  f->base.pMethods = nullptr;
  f->counted = PlannedPath(name);
  f->real = reinterpret_cast<sqlite3_file*>(f + 1);
  if (f->counted && Tick(kFaultOpen)) return SQLITE_CANTOPEN;
  const int rc = g_state.real->xOpen(g_state.real, name, f->real, flags, out_flags);
  // SQLite calls xClose only when pMethods is set; the real file's says whether it must be.
  if (f->real->pMethods != nullptr) f->base.pMethods = &g_methods;
  return rc;
}

int Delete(sqlite3_vfs*, const char* name, int sync_dir) {
  return g_state.real->xDelete(g_state.real, name, sync_dir);
}
int Access(sqlite3_vfs*, const char* name, int flags, int* out) {
  return g_state.real->xAccess(g_state.real, name, flags, out);
}
int FullPathname(sqlite3_vfs*, const char* name, int size, char* out) {
  return g_state.real->xFullPathname(g_state.real, name, size, out);
}
void* DlOpen(sqlite3_vfs*, const char* name) { return g_state.real->xDlOpen(g_state.real, name); }
void DlError(sqlite3_vfs*, int size, char* out) { g_state.real->xDlError(g_state.real, size, out); }
void (*DlSym(sqlite3_vfs*, void* handle, const char* symbol))(void) {
  return g_state.real->xDlSym(g_state.real, handle, symbol);
}
void DlClose(sqlite3_vfs*, void* handle) { g_state.real->xDlClose(g_state.real, handle); }
int Randomness(sqlite3_vfs*, int size, char* out) {
  return g_state.real->xRandomness(g_state.real, size, out);
}
int Sleep(sqlite3_vfs*, int microseconds) {
  return g_state.real->xSleep(g_state.real, microseconds);
}
int CurrentTime(sqlite3_vfs*, double* out) { return g_state.real->xCurrentTime(g_state.real, out); }
int GetLastError(sqlite3_vfs*, int size, char* out) {
  if (g_injected_errno != 0) return std::exchange(g_injected_errno, 0);
  return g_state.real->xGetLastError(g_state.real, size, out);
}
int CurrentTimeInt64(sqlite3_vfs*, sqlite3_int64* out) {
  return g_state.real->xCurrentTimeInt64(g_state.real, out);
}

sqlite3_vfs* Shim() {
  if (g_state.real != nullptr) return &g_vfs;
  g_state.real = sqlite3_vfs_find("unix");
  g_methods = {};
  g_methods.iVersion = 2;  // no xFetch: every page read goes through xRead
  g_methods.xClose = Close;
  g_methods.xRead = Read;
  g_methods.xWrite = Write;
  g_methods.xTruncate = Truncate;
  g_methods.xSync = Sync;
  g_methods.xFileSize = FileSize;
  g_methods.xLock = Lock;
  g_methods.xUnlock = Unlock;
  g_methods.xCheckReservedLock = CheckReservedLock;
  g_methods.xFileControl = FileControl;
  g_methods.xSectorSize = SectorSize;
  g_methods.xDeviceCharacteristics = DeviceCharacteristics;
  g_methods.xShmMap = ShmMap;
  g_methods.xShmLock = ShmLock;
  g_methods.xShmBarrier = ShmBarrier;
  g_methods.xShmUnmap = ShmUnmap;
  g_vfs = {};
  g_vfs.iVersion = 2;
  g_vfs.szOsFile = static_cast<int>(sizeof(FaultFile)) + g_state.real->szOsFile;
  g_vfs.mxPathname = g_state.real->mxPathname;
  g_vfs.zName = "tinbase_fault";
  g_vfs.xOpen = Open;
  g_vfs.xDelete = Delete;
  g_vfs.xAccess = Access;
  g_vfs.xFullPathname = FullPathname;
  g_vfs.xDlOpen = DlOpen;
  g_vfs.xDlError = DlError;
  g_vfs.xDlSym = DlSym;
  g_vfs.xDlClose = DlClose;
  g_vfs.xRandomness = Randomness;
  g_vfs.xSleep = Sleep;
  g_vfs.xCurrentTime = CurrentTime;
  g_vfs.xGetLastError = GetLastError;
  g_vfs.xCurrentTimeInt64 = CurrentTimeInt64;
  return &g_vfs;
}

}  // namespace

const char* FaultErrorName(FaultError error) {
  switch (error) {
    case FaultError::kIoError:
      return "SQLITE_IOERR";
    case FaultError::kFull:
      return "SQLITE_FULL";
    case FaultError::kShortWrite:
      return "short write";
  }
  return "?";
}

ScopedFaultVfs::ScopedFaultVfs(FaultPlan plan) {
  sqlite3_vfs* shim = Shim();
  g_state.armed = false;
  g_state.plan = std::move(plan);
  g_state.count = 0;
  g_state.fired = false;
  g_state.armed = true;
  sqlite3_vfs_register(shim, /*makeDflt=*/1);
}

ScopedFaultVfs::~ScopedFaultVfs() {
  g_state.armed = false;
  sqlite3_vfs_register(g_state.real, /*makeDflt=*/1);
}

int64_t ScopedFaultVfs::operations() const { return g_state.count.load(); }
bool ScopedFaultVfs::fired() const { return g_state.fired.load(); }
void ScopedFaultVfs::Disarm() { g_state.armed = false; }

}  // namespace tinbase::testing
