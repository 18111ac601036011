// WAL write batching: a VFS over the platform's default one that hands the frames of a
// transaction to the operating system in one write instead of two per page.
//
// SQLite writes each WAL frame as two pwrite calls (its 24-byte header, then the page), so a
// polygon edit that changes 25 pages makes 50 system calls at its commit; on the virtual machines
// we measure on a system call costs several microseconds, and the commit was a tenth of a
// feature-by-feature map load. This VFS gathers contiguous non-commit frames in memory and writes
// them, with the commit frame's header, as one call the moment SQLite writes that header; the
// commit frame's page then goes straight through. So every byte of a commit is with the OS before
// SQLite publishes the commit to readers (it does so only after its last frame is written), an
// error in the combined write fails the commit as the direct write would have, and a process
// killed after COMMIT returned loses nothing. Any other call on the log (read, sync, size,
// truncate, close, file control) first writes what is gathered, and any write that does not follow
// the frame pattern goes straight through, so a future SQLite that wrote its log differently would
// only lose the batching. It also cuts a spilling statement journal's writes to lengths the
// default VFS accepts (SQLite writes a whole in-memory chunk a call, as large as the in-memory
// limit SqliteConnection sets, and the unix VFS writes at most 128 KiB - 1 bytes a call and calls the rest
// a full disk). Main database files and other journals are the default VFS's own.
// Thread-safety: register once (done by SqliteConnection::Open); each log file belongs to one connection.
#pragma once

#include <cstdint>

namespace tinbase {

// The VFS's name for sqlite3_open_v2, registered on first call (not as the default VFS).
const char* WalWriteBatchingVfs();

// Process-wide counts of log writes SQLite asked for and writes this VFS made (with a spilling
// statement journal's pieces), for tests and benchmarks.
struct WalWriteCounts {
  int64_t requested = 0;
  int64_t issued = 0;
};
WalWriteCounts WalWriteCountsSoFar();

}  // namespace tinbase
