// The PostgreSQL row stream (db/postgres/pg_copy.h), through InsertRows (db/sql/bulk_write.h),
// which streams a write of many rows with COPY: every value comes back as it went in (text with
// COPY's special characters, bytes, NULL, doubles to the bit, infinities and NaN); a row that
// breaks a constraint fails the write with the mapped error; an abandoned stream leaves the
// connection usable once its transaction is rolled back.
#include "db/postgres/pg_copy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "db/sql/bulk_write.h"
#include "db/sql/connection.h"
#include "tests/support/postgres_support.h"

namespace tinbase::testing {
namespace {

constexpr size_t kRows = 2000;  // above InsertRows' threshold for the stream

struct Row {
  int64_t id;
  double x;
  std::string text;
  std::vector<uint8_t> bytes;
  bool null_text;
};

std::vector<Row> Rows() {
  const std::vector<double> doubles = {0.1,
                                       -0.0,
                                       1e-310,
                                       6378137.000000001,
                                       std::numeric_limits<double>::max(),
                                       std::numeric_limits<double>::infinity(),
                                       -std::numeric_limits<double>::infinity()};
  const std::vector<std::string> texts = {"plain",
                                          "tab\there",
                                          "new\nline",
                                          "back\\slash \\N",
                                          "carriage\rreturn",
                                          "quote ' and \" ok",
                                          "ünïcödé",
                                          ""};
  std::vector<Row> rows;
  for (size_t i = 0; i < kRows; ++i) {
    Row r{static_cast<int64_t>(i) - 1000,
          doubles[i % doubles.size()] * (1 + i * 1e-9),
          texts[i % texts.size()],
          {},
          i % 11 == 0};
    for (size_t b = 0; b < i % 7; ++b) r.bytes.push_back(static_cast<uint8_t>((i * 37 + b) & 255));
    r.bytes.push_back(0);
    r.bytes.push_back('\\');
    rows.push_back(std::move(r));
  }
  return rows;
}

class PgCopyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string target = FreshPostgresStore("copy");
    ASSERT_FALSE(target.empty());
    auto db = Connection::Open(target, Connection::Mode::kCreate);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    db_ = std::move(*db);
    ASSERT_TRUE(db_->Exec("CREATE TABLE t(id bigint NOT NULL, x double precision, "
                          "body text, data bytea)")
                    .ok());
  }

  Status Write(const std::vector<Row>& rows) {
    return InsertRows(*db_, "t(id, x, body, data)", 4, rows.size(),
                      [&](Statement& s, int p, size_t r) {
                        const Row& row = rows[r];
                        s.Bind(p, row.id).Bind(p + 1, row.x);
                        if (row.null_text)
                          s.BindNull(p + 2);
                        else
                          s.Bind(p + 2, row.text);
                        s.BindBlob(p + 3, row.bytes.data(), row.bytes.size());
                      });
  }

  std::unique_ptr<Connection> db_;
};

TEST_F(PgCopyTest, EveryValueComesBackAsItWentIn) {
  const std::vector<Row> rows = Rows();
  ASSERT_TRUE(db_->Exec("BEGIN").ok());
  const Status written = Write(rows);
  ASSERT_TRUE(written.ok()) << written.ToString();
  ASSERT_TRUE(db_->Exec("COMMIT").ok());
  auto read = db_->Prepare("SELECT id, x, body, data FROM t ORDER BY id");
  ASSERT_TRUE(read.ok());
  size_t i = 0;
  while (*(*read)->Step()) {
    ASSERT_LT(i, rows.size());
    const Row& want = rows[i++];
    Statement& s = **read;
    EXPECT_EQ(s.ColumnInt(0), want.id);
    const double x = s.ColumnDouble(1);
    EXPECT_EQ(std::memcmp(&x, &want.x, sizeof x), 0) << want.x << " came back as " << x;
    EXPECT_EQ(s.ColumnIsNull(2), want.null_text);
    if (!want.null_text) {
      EXPECT_EQ(s.ColumnText(2), want.text);
    }
    size_t size = 0;
    const uint8_t* bytes = s.ColumnBlob(3, &size);
    EXPECT_EQ(std::vector<uint8_t>(bytes, bytes + size), want.bytes);
  }
  EXPECT_EQ(i, rows.size());
}

TEST_F(PgCopyTest, NanGoesThroughAsNan) {
  std::vector<Row> rows = Rows();
  for (Row& r : rows) r.x = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(db_->Exec("BEGIN").ok());
  ASSERT_TRUE(Write(rows).ok());
  ASSERT_TRUE(db_->Exec("COMMIT").ok());
  EXPECT_EQ(*db_->QueryInt("SELECT count(*) FROM t WHERE x = 'NaN'"), static_cast<int64_t>(kRows));
}

TEST_F(PgCopyTest, ABrokenConstraintFailsTheWriteAndTheConnectionGoesOn) {
  ASSERT_TRUE(db_->Exec("ALTER TABLE t ADD CHECK (id <> 500)").ok());
  ASSERT_TRUE(db_->Exec("BEGIN").ok());
  const Status written = Write(Rows());
  EXPECT_EQ(written.code(), StatusCode::kConflict) << written.ToString();
  EXPECT_NE(written.message().find("COPY t(id, x, body, data)"), std::string::npos)
      << written.ToString();
  ASSERT_TRUE(db_->Exec("ROLLBACK").ok());
  EXPECT_EQ(*db_->QueryInt("SELECT count(*) FROM t"), 0);
}

TEST_F(PgCopyTest, AnAbandonedStreamWritesNothing) {
  ASSERT_TRUE(db_->Exec("BEGIN").ok());
  {
    auto stream = db_->BeginRowStream("t(id)", 1);
    ASSERT_TRUE(stream.ok() && *stream != nullptr);
    for (int64_t i = 0; i < 10; ++i) ASSERT_TRUE((*stream)->Bind(1, i).Run().ok());
  }  // destroyed unfinished
  // The server failed the transaction: its COMMIT rolls back.
  (void)db_->Exec("COMMIT");
  EXPECT_FALSE(db_->InTransaction());
  EXPECT_EQ(*db_->QueryInt("SELECT count(*) FROM t"), 0);
}

TEST_F(PgCopyTest, AStreamIntoAMissingTableIsRefused) {
  ASSERT_TRUE(db_->Exec("BEGIN").ok());
  auto stream = db_->BeginRowStream("no_such_table(a)", 1);
  ASSERT_FALSE(stream.ok());
  EXPECT_NE(stream.status().message().find("no_such_table"), std::string::npos)
      << stream.status().ToString();
  ASSERT_TRUE(db_->Exec("ROLLBACK").ok());
}

TEST(PgCopyText, EscapesCopysSpecialCharacters) {
  std::string out;
  AppendCopyText("a\tb\nc\rd\\e", &out);
  EXPECT_EQ(out, "a\\tb\\nc\\rd\\\\e");
  out.clear();
  const uint8_t bytes[] = {0x00, 0xab, 0x5c};
  AppendCopyBytea(bytes, sizeof bytes, &out);
  EXPECT_EQ(out, "\\\\x00ab5c");
}

}  // namespace
}  // namespace tinbase::testing
