// Wrong credentials for a PostgreSQL store are named as such, without the password, and change
// nothing; the right ones work. The test server (scripts/pg-server.sh) asks the role
// `tinbase_password` for its password and trusts everyone else.
#include <gtest/gtest.h>

#include "db/sql/connection.h"
#include "tests/support/cli_support.h"
#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

// `url` (postgresql://USER@HOST:PORT/DB) with `user:password` instead of its user.
std::string WithCredentials(const std::string& url, const std::string& credentials) {
  const size_t start = url.find("://") + 3;
  const size_t at = url.find('@', start);
  return url.substr(0, start) + credentials + url.substr(at);
}

TEST(PgCredentialsTest, AWrongPasswordIsNamedWithoutThePassword) {
  const std::string url = PostgresUrl();
  ASSERT_FALSE(url.empty());
  {
    auto admin = Connection::Open(url + "?schema=public", Connection::Mode::kReadWrite);
    ASSERT_TRUE(admin.ok()) << admin.status().ToString();
    ASSERT_TRUE((*admin)
                    ->Exec("DO $$ BEGIN "
                           "IF NOT EXISTS (SELECT 1 FROM pg_roles WHERE rolname = "
                           "'tinbase_password') THEN CREATE ROLE tinbase_password LOGIN PASSWORD "
                           "'right-one'; END IF; END $$; "
                           "GRANT CREATE ON DATABASE tinbase TO tinbase_password")
                    .ok());
  }
  const std::string schema = FreshPostgresStore("creds").substr(url.size());  // "?schema=..."
  const std::string wrong = WithCredentials(url, "tinbase_password:not-the-password") + schema;
  const std::string right = WithCredentials(url, "tinbase_password:right-one") + schema;

  CliResult refused = RunCli("init " + Quote(wrong));
  EXPECT_NE(refused.exit_code, 0) << "the server must ask tinbase_password for its password, as "
                                     "scripts/pg-server.sh sets it up";
  EXPECT_NE(refused.err.find("password authentication failed for user \"tinbase_password\""),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(refused.err.find("not-the-password"), std::string::npos) << refused.err;
  // Nothing was made: the right password finds no store there yet, then makes one.
  CliResult absent = RunCli("info " + Quote(right));
  EXPECT_NE(absent.exit_code, 0);
  EXPECT_NE(absent.err.find("does not exist"), std::string::npos) << absent.err;
  RunWrite(right, "init " + Quote(right));
  EXPECT_EQ(RunCli("info " + Quote(wrong)).exit_code, 1);
}

}  // namespace
}  // namespace tinbase::testing
