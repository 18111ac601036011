#include "core/base/huge_page_malloc.h"

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

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

void RestartWithHugePageMalloc() {
#if defined(TINBASE_HUGE_PAGE_MALLOC)
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  const std::string cmdline((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (cmdline.empty()) return;
  // NUL-separated arguments, each NUL-terminated: pointers into the copy are C strings.
  std::vector<char> text(cmdline.begin(), cmdline.end());
  if (text.back() != '\0') text.push_back('\0');
  std::vector<char*> argv;
  for (size_t start = 0; start < text.size();) {
    argv.push_back(&text[start]);
    while (text[start] != '\0') ++start;
    ++start;
  }
  argv.push_back(nullptr);
  RestartWithHugePageMalloc(argv.data());
#endif
}

}  // namespace tinbase
