// Helpers for tests that drive the tinbase binary: quoting, "write then check --full", and
// "rejected with one clear line and the store unchanged".
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/test_support.h"

namespace tinbase::testing {

inline std::string Quote(const std::string& s) { return "'" + s + "'"; }

// Runs a command that must succeed, then `check --full`, which must pass too.
inline CliResult RunWrite(const std::string& store, const std::string& args) {
  CliResult r = RunCli(args);
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  CliResult check = RunCli("check --full " + Quote(store));
  EXPECT_EQ(check.exit_code, 0) << "check after: " << args << "\n" << check.out << check.err;
  return r;
}

// A command that must fail with one line on stderr containing `expected`, changing nothing.
inline void ExpectRejected(const std::string& store, const std::string& args,
                           const std::string& expected) {
  const auto before = TableChecksums(store);
  CliResult r = RunCli(args);
  EXPECT_NE(r.exit_code, 0) << args;
  EXPECT_NE(r.err.find(expected), std::string::npos) << args << "\nstderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
  EXPECT_EQ(r.err.rfind("tinbase: ", 0), 0u) << r.err;
  EXPECT_EQ(TableChecksums(store), before) << "store changed by rejected: " << args;
}

// The JSON a successful command printed; null (and a failure) when it printed none, so that a
// failed command fails the test with its message instead of a parse exception.
inline nlohmann::json Json(const CliResult& r) {
  EXPECT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  if (!j.is_discarded()) return j;
  ADD_FAILURE() << "the command printed no JSON: " << r.out;
  return nullptr;
}

}  // namespace tinbase::testing
