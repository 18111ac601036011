// The PostgreSQL server of the tests: scripts/test.sh starts a throwaway one
// (scripts/pg-server.sh) and sets TINBASE_TEST_POSTGRES_URL for CTest. A test that needs it
// fails when it is not set, saying how to start one: no test is skipped silently.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <random>
#include <string>

namespace tinbase::testing {

// The server's URL, or "" after a test failure saying how to get one.
inline std::string PostgresUrl() {
  const char* url = std::getenv("TINBASE_TEST_POSTGRES_URL");
  if (url == nullptr || *url == '\0') {
    ADD_FAILURE() << "TINBASE_TEST_POSTGRES_URL is not set: run the tests with scripts/test.sh, "
                     "or start a server with `scripts/pg-server.sh start DIR` and export the URL "
                     "it prints";
    return "";
  }
  return url;
}

// A store target in a schema of that server no other test uses ("" when there is no server).
// The process id alone is not enough: a server that outlives many test runs sees ids again.
inline std::string FreshPostgresStore(const std::string& label) {
  static std::atomic<int> counter{0};
  static const unsigned nonce = std::random_device{}() % 1000000;
  const std::string url = PostgresUrl();
  if (url.empty()) return "";
  return url + "?schema=t_" + label + "_" + std::to_string(getpid()) + "_" + std::to_string(nonce) +
         "_" + std::to_string(counter++);
}

}  // namespace tinbase::testing
