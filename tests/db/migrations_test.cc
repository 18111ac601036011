// The migrations produce exactly schema/sqlite.sql; stores open, refuse and migrate as promised.
#include "db/migrations.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "db/store.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// Every schema object as (type, name, normalised SQL), in name order.
std::string SchemaOf(Connection& db) {
  auto stmt = db.Prepare(
      "SELECT type, name, sql FROM sqlite_master WHERE name NOT LIKE 'sqlite_%' ORDER BY name");
  EXPECT_TRUE(stmt.ok());
  std::string out;
  while (*(*stmt)->Step()) {
    std::string sql = (*stmt)->ColumnText(2);
    std::string squeezed;
    for (char c : sql) {
      if (std::isspace(static_cast<unsigned char>(c))) {
        if (!squeezed.empty() && squeezed.back() != ' ') squeezed += ' ';
      } else {
        squeezed += c;
      }
    }
    out += (*stmt)->ColumnText(0) + " " + (*stmt)->ColumnText(1) + ": " + squeezed + "\n";
  }
  return out;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Migrations, ProduceExactlyTheSchemaFile) {
  TempDir dir;
  auto store = Store::Create(dir.Path("a.tinbase"), "");
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  auto reference = Connection::Open(dir.Path("ref.sqlite"), Connection::Mode::kCreate);
  ASSERT_TRUE(reference.ok());
  ASSERT_TRUE((*reference)->Exec(ReadFile(std::string(TINBASE_SCHEMA_DIR) + "/sqlite.sql")).ok());
  EXPECT_EQ(SchemaOf((*store)->db()), SchemaOf(**reference));
  EXPECT_EQ((*store)->SchemaVersion(), LatestSchemaVersion());
}

TEST(Migrations, AreNumberedWithoutGaps) {
  const auto& list = SqliteMigrations();
  ASSERT_GE(list.size(), 2u);
  for (size_t i = 0; i < list.size(); ++i) EXPECT_EQ(list[i].version, static_cast<int>(i + 1));
}

TEST(Store, OlderStoreIsMigratedForward) {
  TempDir dir;
  const std::string path = dir.Path("old.tinbase");
  {
    auto db = Connection::Open(path, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE(
        (*db)->Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId)).ok());
    ASSERT_TRUE(MigrateStore(**db, 1).ok());
    ASSERT_TRUE((*db)->Exec("INSERT INTO meta(key, value) VALUES ('note', 'kept')").ok());
  }
  auto store = Store::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  EXPECT_EQ(*(*store)->db().QueryInt("PRAGMA user_version"), LatestSchemaVersion());
  auto note = (*store)->GetMeta("note");
  ASSERT_TRUE(note.ok());
  EXPECT_EQ(note->value_or(""), "kept");
  EXPECT_TRUE((*store)->db().QueryInt("SELECT count(*) FROM triangles").ok());
}

// The first column of the first row of `sql`, as text.
std::string Text(Connection& db, const std::string& sql) {
  auto stmt = db.Prepare(sql);
  EXPECT_TRUE(stmt.ok());
  if (!stmt.ok() || !*(*stmt)->Step()) return "";
  return (*stmt)->ColumnText(0);
}

// 0009 rebuilds the triangles table without the foreign key on tag: every row stays as it was.
TEST(Store, Migration0009KeepsTheTriangleRows) {
  TempDir dir;
  const std::string path = dir.Path("v8.tinbase");
  const std::string rows =
      "SELECT group_concat(id || ':' || surface || ':' || v0 || ':' || v1 || ':' || v2 || ':' || "
      "coalesce(n0, '-') || ':' || coalesce(n1, '-') || ':' || coalesce(n2, '-') || ':' || "
      "visible || ':' || coalesce(tag, '-') || ':' || block, ' ') FROM (SELECT * FROM triangles "
      "ORDER BY id)";
  std::string before;
  {
    auto db = Connection::Open(path, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok());
    Connection& d = **db;
    ASSERT_TRUE(d.Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId)).ok());
    ASSERT_TRUE(MigrateStore(d, 8).ok());
    ASSERT_TRUE(d.Exec("INSERT INTO surfaces(id, name, kind, method, block_origin_x, "
                       "block_origin_y, block_size) VALUES (3, 's', 'free', 'test', 0, 0, 1);"
                       "INSERT INTO tags(id, value) VALUES (7, 'granite');"
                       "INSERT INTO triangles VALUES (10, 3, 1, 2, 3, 11, NULL, NULL, 1, 7, 5),"
                       "(11, 3, 3, 2, 4, NULL, 10, NULL, 0, NULL, 16777222)")
                    .ok());
    before = Text(d, rows);
    ASSERT_NE(before.find("10:3:1:2:3:11:-:-:1:7:5"), std::string::npos) << before;
  }
  auto store = Store::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  Connection& d = (*store)->db();
  EXPECT_EQ(*d.QueryInt("PRAGMA user_version"), LatestSchemaVersion());
  EXPECT_EQ(Text(d, rows), before);
  EXPECT_EQ(*d.QueryInt("SELECT count(*) FROM pragma_foreign_key_list('triangles')"), 1)
      << "only surface is a declared key";
  EXPECT_TRUE(d.Exec("UPDATE triangles SET tag = 999 WHERE id = 10").ok())
      << "an unknown tag is for tinbase check to report";
}

// 0014 rebuilds features (and with it constraints, which refers to it) for the new modes: every
// feature, every constraint with its rowid (the GeoPackage fid) stays, the cascade from a feature
// to its constraints still holds, and the layers read the rebuilt tables.
TEST(Store, Migration0014KeepsFeaturesAndTheirConstraints) {
  TempDir dir;
  const std::string path = dir.Path("v13.tinbase");
  const std::string feature_rows =
      "SELECT group_concat(id || ':' || surface || ':' || coalesce(name, '-') || ':' || mode || "
      "':' || coalesce(level, '-') || ':' || coalesce(tag, '-') || ':' || attributes || ':' || "
      "hex(geometry) || ':' || min_x || ':' || min_y || ':' || max_x || ':' || max_y || ':' || tx, "
      "' ') FROM (SELECT * FROM features ORDER BY id)";
  const std::string constraint_rows =
      "SELECT group_concat(rowid || ':' || surface || ':' || va || ':' || vb || ':' || "
      "coalesce(feature, '-'), ' ') FROM (SELECT rowid, * FROM constraints ORDER BY rowid)";
  std::string features_before;
  std::string constraints_before;
  {
    auto db = Connection::Open(path, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok());
    Connection& d = **db;
    ASSERT_TRUE(d.Exec("PRAGMA foreign_keys = ON").ok());
    ASSERT_TRUE(d.Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId)).ok());
    ASSERT_TRUE(MigrateStore(d, 13).ok());
    ASSERT_TRUE(d.Exec("INSERT INTO surfaces(id, name, kind, method, block_origin_x, "
                       "block_origin_y, block_size) VALUES (3, 's', 'free', 'test', 0, 0, 1);"
                       "INSERT INTO tags(id, value) VALUES (7, 'granite');"
                       "INSERT INTO features VALUES (5, 3, 'fault', 'breakline', NULL, NULL, "
                       "'{\"a\":1}', X'0105', 0, 0, 4, 4, 1),"
                       "(9, 3, NULL, 'fill', 2.5, 7, '{}', X'0106', 1, 1, 2, 2, 2);"
                       "INSERT INTO constraints(rowid, surface, va, vb, feature) VALUES "
                       "(4, 3, 1, 2, 5), (8, 3, 2, 6, 5), (12, 3, 3, 4, NULL)")
                    .ok());
    features_before = Text(d, feature_rows);
    constraints_before = Text(d, constraint_rows);
    ASSERT_EQ(constraints_before, "4:3:1:2:5 8:3:2:6:5 12:3:3:4:-");
  }
  auto store = Store::Open(path);
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  Connection& d = (*store)->db();
  EXPECT_EQ(*d.QueryInt("PRAGMA user_version"), LatestSchemaVersion());
  EXPECT_EQ(Text(d, feature_rows), features_before);
  EXPECT_EQ(Text(d, constraint_rows), constraints_before);
  EXPECT_EQ(Text(d, "SELECT group_concat(z_from) FROM features"), "dem,dem");
  EXPECT_EQ(Text(d, "SELECT group_concat(kind) FROM constraints"), "hard,hard,hard");
  EXPECT_EQ(*d.QueryInt("SELECT count(*) FROM pragma_foreign_key_check"), 0);
  EXPECT_EQ(Text(d, "SELECT group_concat(fid || ':' || kind) FROM tinbase_constraints"),
            "4:hard,8:hard,12:hard");
  EXPECT_EQ(Text(d, "SELECT group_concat(fid || ':' || mode) FROM tinbase_breaklines"),
            "5:breakline");
  EXPECT_EQ(Text(d, "SELECT group_concat(fid) FROM tinbase_features"), "9");

  EXPECT_TRUE(d.Exec("INSERT INTO features(id, surface, mode, geometry, min_x, min_y, max_x, "
                     "max_y, tx, z_from) VALUES (10, 3, 'softline', X'', 0, 0, 1, 1, 3, "
                     "'feature'), (11, 3, 'points', X'', 0, 0, 1, 1, 3, 'dem')")
                  .ok());
  EXPECT_TRUE(d.Exec("INSERT INTO constraints(surface, va, vb, feature, kind) "
                     "VALUES (3, 7, 8, 10, 'soft')")
                  .ok());
  EXPECT_FALSE(d.Exec("UPDATE features SET mode = 'wiggle' WHERE id = 10").ok());
  EXPECT_FALSE(d.Exec("UPDATE features SET z_from = 'lidar' WHERE id = 10").ok());
  EXPECT_FALSE(d.Exec("UPDATE constraints SET kind = 'firm' WHERE feature = 10").ok());
  EXPECT_EQ(Text(d, "SELECT group_concat(fid || ':' || mode) FROM tinbase_breaklines"),
            "5:breakline,10:softline");
  EXPECT_EQ(Text(d, "SELECT group_concat(fid) FROM tinbase_features"), "9")
      << "a points feature is in no feature layer";

  ASSERT_TRUE(d.Exec("DELETE FROM features WHERE id = 5").ok());
  EXPECT_EQ(Text(d, constraint_rows), "12:3:3:4:- 13:3:7:8:10")
      << "deleting a feature still deletes its constraints";
}

TEST(Store, NewerStoreIsRefusedWithAClearMessage) {
  TempDir dir;
  const std::string path = dir.Path("new.tinbase");
  { ASSERT_TRUE(Store::Create(path, "").ok()); }
  {
    auto db = Connection::Open(path, Connection::Mode::kReadWrite);
    ASSERT_TRUE((*db)->Exec("PRAGMA user_version = 999").ok());
  }
  auto store = Store::Open(path);
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.status().message().find("newer tinbase"), std::string::npos)
      << store.status().message();
}

TEST(Store, ForeignFilesAreNotStores) {
  TempDir dir;
  const std::string text = dir.Path("notes.txt");
  std::ofstream(text) << "not a database at all, just some text that is long enough\n";
  auto a = Store::Open(text);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.status().message().find("not a tinbase store"), std::string::npos);

  const std::string other = dir.Path("other.sqlite");
  {
    ASSERT_TRUE(
        (*Connection::Open(other, Connection::Mode::kCreate))->Exec("CREATE TABLE t(x)").ok());
  }
  auto b = Store::Open(other);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.status().message().find("not a tinbase store"), std::string::npos);

  auto c = Store::Open(dir.Path("missing.tinbase"));
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kNotFound);
}

TEST(Store, CreateRecordsTheCrsAndRefusesToOverwrite) {
  TempDir dir;
  const std::string path = dir.Path("s.tinbase");
  auto store = Store::Create(path, "EPSG:32632");
  ASSERT_TRUE(store.ok()) << store.status().ToString();
  auto crs = (*store)->GetCrs();
  ASSERT_TRUE(crs.ok() && crs->has_value());
  EXPECT_EQ((*crs)->Epsg().value_or(0), 32632);
  EXPECT_EQ(*(*store)->db().QueryInt("PRAGMA foreign_keys"), 1);
  auto again = Store::Create(path, "");
  EXPECT_FALSE(again.ok());
  auto bad = Store::Create(dir.Path("t.tinbase"), "EPSG:999999999");
  EXPECT_FALSE(bad.ok());
}

TEST(Store, UncommittedWriteTransactionRollsBack) {
  TempDir dir;
  auto store = Store::Create(dir.Path("s.tinbase"), "");
  ASSERT_TRUE(store.ok());
  {
    auto tx = (*store)->BeginWrite();
    ASSERT_TRUE(tx.ok());
    ASSERT_TRUE((*store)->SetMeta("k", "v").ok());
  }
  EXPECT_FALSE((*store)->GetMeta("k")->has_value());
}

}  // namespace
}  // namespace tinbase
