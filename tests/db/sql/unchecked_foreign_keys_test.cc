// Foreign keys go unchecked while an UncheckedForeignKeys lives, inside a transaction too, and
// are enforced again after it (and stay off when they were off).
#include "db/sql/unchecked_foreign_keys.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::unique_ptr<Connection> ParentAndChild(const TempDir& dir) {
  auto db = Connection::Open(dir.Path("fk.db"), Connection::Mode::kCreate);
  EXPECT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_TRUE((*db)->Exec("PRAGMA foreign_keys = ON").ok());
  EXPECT_TRUE((*db)
                  ->Exec("CREATE TABLE parent(id INTEGER PRIMARY KEY); "
                         "CREATE TABLE child(id INTEGER PRIMARY KEY, p INTEGER REFERENCES "
                         "parent(id)); INSERT INTO parent(id) VALUES (1); "
                         "INSERT INTO child(id, p) VALUES (1, 1)")
                  .ok());
  return std::move(*db);
}

TEST(UncheckedForeignKeysTest, UncheckedWhileItLivesInsideATransaction) {
  TempDir dir;
  auto db = ParentAndChild(dir);
  ASSERT_TRUE(db->Exec("BEGIN IMMEDIATE").ok());
  EXPECT_FALSE(db->Exec("UPDATE child SET p = 7 WHERE id = 1").ok());
  {
    auto unchecked = UncheckedForeignKeys::Begin(*db);
    ASSERT_TRUE(unchecked.ok()) << unchecked.status().ToString();
    EXPECT_TRUE(db->Exec("UPDATE child SET p = 7 WHERE id = 1").ok());
    EXPECT_TRUE(db->Exec("UPDATE child SET p = 1 WHERE id = 1").ok());
  }
  EXPECT_FALSE(db->Exec("UPDATE child SET p = 8 WHERE id = 1").ok());
  ASSERT_TRUE(db->Exec("COMMIT").ok());
  EXPECT_EQ(*db->QueryInt("PRAGMA foreign_keys"), 1);
  EXPECT_EQ(*db->QueryInt("SELECT p FROM child WHERE id = 1"), 1);
}

TEST(UncheckedForeignKeysTest, LeavesKeysOffWhenTheyWereOff) {
  TempDir dir;
  auto db = ParentAndChild(dir);
  ASSERT_TRUE(db->Exec("PRAGMA foreign_keys = OFF").ok());
  { ASSERT_TRUE(UncheckedForeignKeys::Begin(*db).ok()); }
  EXPECT_EQ(*db->QueryInt("PRAGMA foreign_keys"), 0);
  auto was_on = db->SetForeignKeys(true);
  ASSERT_TRUE(was_on.ok());
  EXPECT_FALSE(*was_on);
  EXPECT_FALSE(db->Exec("UPDATE child SET p = 9 WHERE id = 1").ok());
}

}  // namespace
}  // namespace tinbase
