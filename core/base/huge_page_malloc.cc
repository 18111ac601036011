#include "core/base/huge_page_malloc.h"

#include <cstdlib>
#include <string>

#if defined(__linux__)
#include <unistd.h>
#endif

// Nested: a preprocessor without glibc has no __GLIBC_PREREQ to call.
#if defined(__linux__) && defined(__GLIBC__)
#if __GLIBC_PREREQ(2, 35)
#define TINBASE_HUGE_PAGE_MALLOC 1
#endif
#endif

namespace tinbase {

void RestartWithHugePageMalloc(char** argv) {
#if defined(TINBASE_HUGE_PAGE_MALLOC)
  // Set before the restart: a second start never restarts again, whatever glibc does with
  // GLIBC_TUNABLES.
  constexpr const char* kRestarted = "TINBASE_HUGE_PAGES_RESTARTED";
  if (std::getenv(kRestarted) != nullptr) return;
  const char* choice = std::getenv("TINBASE_HUGE_PAGES");
  if (choice != nullptr && std::string(choice) == "0") return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string before = tunables != nullptr ? tunables : "";
  if (before.find("glibc.malloc.hugetlb") != std::string::npos) return;
  const std::string wanted =
      before.empty() ? "glibc.malloc.hugetlb=1" : before + ":glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
  if (setenv(kRestarted, "1", 1) == 0) execv("/proc/self/exe", argv);
  // Still here: the restart failed; go on as the process is.
  unsetenv(kRestarted);
  if (tunables != nullptr) {
    setenv("GLIBC_TUNABLES", before.c_str(), 1);
  } else {
    unsetenv("GLIBC_TUNABLES");
  }
#else
  (void)argv;
#endif
}

}  // namespace tinbase
