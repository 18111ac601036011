// Huge-page malloc: runs a program on glibc's malloc backed by transparent huge pages.
//
// Building and importing large surfaces touches gigabytes of fresh memory, and on a VM the first
// touch of each 4 KiB page is a costly fault: on our 2-core CI VM a 4 M-point LiDAR import into a
// store ran 1.2-1.7x faster with 2 MiB pages. glibc backs its heap with huge pages only when told
// so at start-up (GLIBC_TUNABLES=glibc.malloc.hugetlb=1, glibc 2.35 and later), so a program
// calls RestartWithHugePageMalloc first thing in main, or before it starts its work. The restart
// loads the program's shared libraries again, so the CLI restarts only for its bulk commands and
// for whole-surface reads of large stores (apps/tinbase/bulk_commands.h).
// Thread-safety: call before any thread starts.
#pragma once

namespace tinbase {

// Executes the program again, once, with glibc.malloc.hugetlb=1 added to GLIBC_TUNABLES, and
// does not return when that succeeds. Returns, changing nothing, when the environment already
// names that tunable (the user's choice), when this process is that second start, when
// TINBASE_HUGE_PAGES is 0, off Linux or glibc before 2.35, or when the restart fails.
void RestartWithHugePageMalloc(char** argv);

// The same with the arguments the process was started with (/proc/self/cmdline), for a program
// that decides late, once it knows how much data it will read. Call before any thread starts
// and before anything is written.
void RestartWithHugePageMalloc();

}  // namespace tinbase
