#include "db/postgres/pg_connection.h"

#include <libpq-fe.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>

#include "core/tin/block_grid.h"
#include "db/postgres/pg_copy.h"

namespace tinbase {

namespace {

// libpq's messages end with a newline and may run over several lines; a Status holds one line.
std::string FirstLine(const char* message) {
  std::string text = message == nullptr ? "" : message;
  const size_t end = text.find('\n');
  if (end != std::string::npos) text.resize(end);
  if (text.rfind("ERROR:  ", 0) == 0) text = text.substr(8);
  return text;
}

// A name for SQL text: the schema is checked to be a plain identifier (store_url.cc), quoted
// all the same.
std::string QuoteIdentifier(const std::string& name) { return "\"" + name + "\""; }

bool IsWordByte(char c) {
  return c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
}

struct ResultDeleter {
  void operator()(PGresult* r) const { PQclear(r); }
};
using ResultPtr = std::unique_ptr<PGresult, ResultDeleter>;

}  // namespace

Status StatusFromPg(const pg_result* result, const pg_conn* conn, std::string_view context) {
  const ExecStatusType status = result == nullptr ? PGRES_FATAL_ERROR : PQresultStatus(result);
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return Status::Ok();
  const char* state = result == nullptr ? nullptr : PQresultErrorField(result, PG_DIAG_SQLSTATE);
  std::string message(context);
  message += ": ";
  message += FirstLine(result != nullptr && *PQresultErrorMessage(result) != '\0'
                           ? PQresultErrorMessage(result)
                           : PQerrorMessage(conn));
  const std::string code = state == nullptr ? "" : state;
  if (code.rfind("40", 0) == 0 || code == "55P03" || code == "57014") return Status::Busy(message);
  if (code.rfind("23", 0) == 0) return Status::Conflict(message);
  if (code == "XX001" || code == "XX002") return Status::Corruption(message);
  if (code.rfind("22", 0) == 0 || code.rfind("42", 0) == 0) return Status::InvalidArgument(message);
  return Status::IOError(message);
}

std::string PostgresParameters(std::string_view sql) {
  std::string out;
  out.reserve(sql.size() + 16);
  int next = 1;
  for (size_t i = 0; i < sql.size(); ++i) {
    const char c = sql[i];
    if (c == '\'' || c == '"') {  // a quoted text or name, to its closing quote
      const size_t end = sql.find(c, i + 1);
      const size_t stop = end == std::string_view::npos ? sql.size() : end + 1;
      out.append(sql.substr(i, stop - i));
      i = stop - 1;
    } else if (c == '-' && i + 1 < sql.size() && sql[i + 1] == '-') {  // a comment, to its line end
      const size_t end = sql.find('\n', i);
      const size_t stop = end == std::string_view::npos ? sql.size() : end;
      out.append(sql.substr(i, stop - i));
      i = stop - 1;
    } else if (c == 'b' && sql.substr(i, 2) == "by" && (i == 0 || !IsWordByte(sql[i - 1])) &&
               (i + 2 == sql.size() || !IsWordByte(sql[i + 2]))) {
      out += "\"by\"";  // the column dem_blocks.by, a reserved word in PostgreSQL
      ++i;
    } else if (c == '?') {
      size_t digits = i + 1;
      while (digits < sql.size() && sql[digits] >= '0' && sql[digits] <= '9') ++digits;
      if (digits > i + 1) {
        out += '$';
        out.append(sql.substr(i + 1, digits - i - 1));
        i = digits - 1;
      } else {
        out += '$' + std::to_string(next++);
      }
    } else {
      out += c;
    }
  }
  return out;
}

std::string PostgresFloatText(double value) {
  // The shortest text that reads back as the same double (std::to_chars), so a round trip
  // through the server changes no bit of a coordinate.
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text = error == std::errc() ? std::string(buffer, end) : std::string("NaN");
  if (text == "inf") text = "Infinity";
  if (text == "-inf") text = "-Infinity";
  if (text == "nan" || text == "-nan") text = "NaN";
  return text;
}

// ---- PgStatement -------------------------------------------------------------------------------

PgStatement::PgStatement(pg_conn* conn, std::string name, std::string sql, int64_t* changes)
    : Statement(std::move(sql)), conn_(conn), name_(std::move(name)), changes_(changes) {}

PgStatement::~PgStatement() { PQclear(result_); }

PgStatement::Parameter& PgStatement::At(int index) {
  const size_t i = static_cast<size_t>(index - 1);
  if (parameters_.size() <= i) parameters_.resize(i + 1);
  return parameters_[i];
}

PgStatement& PgStatement::Bind(int index, int64_t value) {
  At(index) = {std::to_string(value), false};
  return *this;
}

PgStatement& PgStatement::Bind(int index, double value) {
  At(index) = {PostgresFloatText(value), false};
  return *this;
}

PgStatement& PgStatement::Bind(int index, std::string_view text) {
  At(index) = {std::string(text), false};
  return *this;
}

PgStatement& PgStatement::BindStaticText(int index, const char* text) {
  return Bind(index, std::string_view(text));
}

PgStatement& PgStatement::BindBlob(int index, const void* data, size_t size) {
  At(index) = {std::string(static_cast<const char*>(data), size), true};
  return *this;
}

PgStatement& PgStatement::BindNull(int index) {
  At(index) = {std::nullopt, false};
  return *this;
}

Status PgStatement::Execute() {
  std::vector<const char*> values(parameters_.size());
  std::vector<int> lengths(parameters_.size());
  std::vector<int> formats(parameters_.size());
  for (size_t i = 0; i < parameters_.size(); ++i) {
    const Parameter& p = parameters_[i];
    values[i] = p.value ? p.value->data() : nullptr;
    lengths[i] = p.value ? static_cast<int>(p.value->size()) : 0;
    formats[i] = p.binary ? 1 : 0;
  }
  result_ = PQexecPrepared(conn_, name_.c_str(), static_cast<int>(parameters_.size()),
                           values.data(), lengths.data(), formats.data(), /*resultFormat=*/0);
  Status status = StatusFromPg(result_, conn_, sql().substr(0, 60));
  if (!status.ok()) return status;
  const char* tuples = PQcmdTuples(result_);
  *changes_ = *tuples == '\0' ? 0 : std::strtoll(tuples, nullptr, 10);
  row_ = -1;
  return Status::Ok();
}

Result<bool> PgStatement::Step() {
  if (result_ == nullptr) TB_RETURN_IF_ERROR(Execute());
  ++row_;
  return row_ < PQntuples(result_);
}

Status PgStatement::Run() {
  Result<bool> r = Step();
  Reset();
  return r.status();
}

void PgStatement::Reset() {
  PQclear(result_);
  result_ = nullptr;
  row_ = -1;
  parameters_.clear();
}

int PgStatement::ColumnCount() const { return result_ == nullptr ? 0 : PQnfields(result_); }

int64_t PgStatement::ColumnInt(int index) const {
  const char* text = PQgetvalue(result_, row_, index);
  if (text[0] == 't' && text[1] == '\0') return 1;  // a boolean
  if (text[0] == 'f' && text[1] == '\0') return 0;
  int64_t value = 0;
  const auto [end, error] = std::from_chars(text, text + std::strlen(text), value);
  if (error == std::errc() && *end == '\0') return value;
  return static_cast<int64_t>(std::strtod(text, nullptr));  // a numeric or float column
}

double PgStatement::ColumnDouble(int index) const {
  return std::strtod(PQgetvalue(result_, row_, index), nullptr);
}

std::string PgStatement::ColumnText(int index) const {
  return std::string(PQgetvalue(result_, row_, index),
                     static_cast<size_t>(PQgetlength(result_, row_, index)));
}

bool PgStatement::ColumnIsNull(int index) const { return PQgetisnull(result_, row_, index) != 0; }

const uint8_t* PgStatement::ColumnBlob(int index, size_t* size) const {
  size_t length = 0;
  unsigned char* bytes = PQunescapeBytea(
      reinterpret_cast<const unsigned char*>(PQgetvalue(result_, row_, index)), &length);
  blob_.assign(bytes, bytes + length);
  PQfreemem(bytes);
  *size = blob_.size();
  return blob_.data();
}

// ---- PgConnection ------------------------------------------------------------------------------

PgConnection::PgConnection(pg_conn* conn, std::string schema, std::string label)
    : conn_(conn),
      schema_(std::move(schema)),
      label_(std::move(label)),
      lock_key_(static_cast<int64_t>(std::hash<std::string>()("tinbase/" + schema_) >> 1)) {}

PgConnection::~PgConnection() {
  cache_.clear();
  PQfinish(conn_);
}

Result<std::unique_ptr<PgConnection>> PgConnection::Open(const std::string& conninfo,
                                                         const std::string& schema,
                                                         const std::string& label, Mode mode) {
  PGconn* raw = PQconnectdb(conninfo.c_str());
  if (PQstatus(raw) != CONNECTION_OK) {
    Status s = Status::IOError(label + ": cannot connect: " + FirstLine(PQerrorMessage(raw)));
    PQfinish(raw);
    return s;
  }
  std::unique_ptr<PgConnection> db(new PgConnection(raw, schema, label));
  TB_RETURN_IF_ERROR(db->Exec("SET client_min_messages = warning"));
  TB_ASSIGN_OR_RETURN(
      int64_t exists,
      db->QueryInt("SELECT count(*) FROM pg_namespace WHERE nspname = '" + schema + "'"));
  if (mode == Mode::kCreate) {
    if (exists != 0) {
      TB_RETURN_IF_ERROR(db->Exec("SET search_path TO " + QuoteIdentifier(schema) + ", public"));
      TB_ASSIGN_OR_RETURN(bool store, db->HasStoreTable());
      if (store) return Status::InvalidArgument(label + ": a store already exists there");
    } else {
      TB_RETURN_IF_ERROR(db->Exec("CREATE SCHEMA " + QuoteIdentifier(schema)));
    }
  } else if (exists == 0) {
    return Status::NotFound(label + ": no such store (schema '" + schema + "' does not exist)");
  }
  TB_RETURN_IF_ERROR(db->Exec("SET search_path TO " + QuoteIdentifier(schema) + ", public"));
  // A writer waiting for another's lock gives up after this, as SQLite's busy timeout does.
  TB_RETURN_IF_ERROR(db->Exec("SET lock_timeout = '10s'"));
  if (mode == Mode::kReadOnly)
    TB_RETURN_IF_ERROR(db->Exec("SET default_transaction_read_only = on"));
  return db;
}

Status PgConnection::Exec(std::string_view sql) {
  const std::string text = PostgresParameters(sql);
  ResultPtr result(PQexec(conn_, text.c_str()));
  TB_RETURN_IF_ERROR(StatusFromPg(result.get(), conn_, text.substr(0, 60)));
  const char* tuples = PQcmdTuples(result.get());
  changes_ = *tuples == '\0' ? 0 : std::strtoll(tuples, nullptr, 10);
  total_changes_ += changes_;
  return Status::Ok();
}

Result<std::unique_ptr<Statement>> PgConnection::Prepare(std::string_view sql) {
  const std::string name = "tb" + std::to_string(next_statement_++);
  const std::string text = PostgresParameters(sql);
  ResultPtr result(PQprepare(conn_, name.c_str(), text.c_str(), 0, nullptr));
  TB_RETURN_IF_ERROR(
      StatusFromPg(result.get(), conn_, "preparing " + std::string(sql.substr(0, 60))));
  return std::unique_ptr<Statement>(new PgStatement(conn_, name, std::string(sql), &changes_));
}

Result<Statement*> PgConnection::Cached(std::string_view sql) {
  auto it = cache_.find(std::string(sql));
  if (it != cache_.end()) {
    it->second->Reset();
    return it->second.get();
  }
  TB_ASSIGN_OR_RETURN(auto stmt, Prepare(sql));
  auto* raw = static_cast<PgStatement*>(stmt.release());
  cache_.emplace(std::string(sql), std::unique_ptr<PgStatement>(raw));
  return static_cast<Statement*>(raw);
}

Result<int64_t> PgConnection::DataVersion() {
  // Every write that changes a surface appends one row to `changes`, and none is ever deleted:
  // their count says whether anything a cache holds may have changed. (Not the largest number:
  // concurrent writers commit their numbers out of order.) The rows of this connection's open
  // transaction (xmin is its id) do not count: they are not another's commit.
  return QueryInt(
      "SELECT count(*) FROM changes "
      "WHERE xmin IS DISTINCT FROM pg_current_xact_id_if_assigned()::xid");
}

Result<int64_t> PgConnection::SettledChange() {
  if (InTransaction()) return settled_at_begin_;
  return ReadSettledChange();
}

Result<int64_t> PgConnection::ReadSettledChange() {
  // A writer draws its number (the trigger's nextval) inside its INSERT INTO changes, so it holds
  // that table's RowExclusiveLock from before it draws until it ends. Hence, in this order: the
  // numbers drawn so far; then, if no other transaction holds that lock, each of them was drawn
  // by a transaction that has ended, and a snapshot taken after this sees the committed ones.
  // When one does, its number is unknown (its row is not visible): nothing is settled beyond
  // what the reader sees without a gap. Numbers drawn later are larger than all of these. A
  // role that may not read the sequence (or a store without it) settles nothing either.
  TB_ASSIGN_OR_RETURN(
      const int64_t drawn,
      QueryInt("SELECT CASE WHEN has_sequence_privilege(to_regclass('changes_tx_seq'), "
               "'SELECT, USAGE') THEN "
               "coalesce(pg_sequence_last_value(to_regclass('changes_tx_seq')), 0) "
               "ELSE 0 END"));
  TB_ASSIGN_OR_RETURN(
      const int64_t writers,
      QueryInt("SELECT count(*) FROM pg_locks WHERE locktype = 'relation' "
               "AND database = (SELECT oid FROM pg_database WHERE datname = current_database()) "
               "AND relation = to_regclass('changes') AND mode = 'RowExclusiveLock' "
               "AND pid <> pg_backend_pid()"));
  return writers == 0 ? drawn : 0;
}

Status PgConnection::BeginWrite() {
  TB_RETURN_IF_ERROR(Exec("BEGIN ISOLATION LEVEL READ COMMITTED"));
  Status locked = Exec("SELECT pg_advisory_xact_lock(" + std::to_string(lock_key_) + ")");
  if (!locked.ok()) (void)Exec("ROLLBACK");
  // Every other writer of the store waits for this lock, region writers included (they hold it
  // shared until they have committed): no number is in flight while it is held.
  settled_at_begin_ = std::numeric_limits<int64_t>::max();
  return locked;
}

Status PgConnection::BeginRead() {
  settled_at_begin_ = 0;
  TB_RETURN_IF_ERROR(Exec("BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY"));
  Status s = Exec("SELECT 1");
  if (!s.ok()) (void)Exec("ROLLBACK");
  return s;
}

Status PgConnection::BeginRegionWrite() {
  TB_RETURN_IF_ERROR(Exec("SELECT pg_advisory_lock_shared(" + std::to_string(lock_key_) + ")"));
  region_write_lock_ = true;
  // Read before the snapshot is taken, for the tile update an edit may run before it commits.
  Result<int64_t> settled = ReadSettledChange();
  if (!settled.ok()) {
    ReleaseRegionWriteLock();
    return settled.status();
  }
  settled_at_begin_ = *settled;
  Status begun = Exec("BEGIN ISOLATION LEVEL REPEATABLE READ");
  if (!begun.ok()) ReleaseRegionWriteLock();
  return begun;
}

void PgConnection::ReleaseRegionWriteLock() {
  if (!region_write_lock_) return;
  region_write_lock_ = false;
  // A dropped connection has lost the lock with its session.
  (void)Exec("SELECT pg_advisory_unlock_shared(" + std::to_string(lock_key_) + ")");
}

int64_t PgConnection::SurfaceLockKey(int64_t surface) const {
  return static_cast<int64_t>(
      std::hash<std::string>()("tinbase/" + schema_ + "/" + std::to_string(surface)) >> 1);
}

Status PgConnection::LockRegion(int64_t surface, const std::vector<int64_t>& blocks,
                                bool whole_surface) {
  const int64_t key = SurfaceLockKey(surface);
  if (whole_surface) return Exec("SELECT pg_advisory_xact_lock(" + std::to_string(key) + ")");
  // The two-number form of the lock: (the surface, the block). A block id is by * 2^24 + bx;
  // the low 15 bits of by and 16 of bx make the second number, so only blocks tens of thousands
  // of blocks apart share a lock (they then wait for each other, which is never wrong).
  const auto surface_part = static_cast<int32_t>(key & 0x7fffffff);
  std::vector<int32_t> parts;
  parts.reserve(blocks.size());
  for (int64_t block : blocks) {
    const int64_t bx = BlockGrid::ColumnOfPacked(block), by = BlockGrid::RowOfPacked(block);
    parts.push_back(static_cast<int32_t>(((by & 0x7fff) << 16) | (bx & 0xffff)));
  }
  std::sort(parts.begin(), parts.end());
  parts.erase(std::unique(parts.begin(), parts.end()), parts.end());
  // PostgreSQL evaluates a select list left to right, so each statement takes its locks in the
  // sorted order, and the statements follow each other in that order too. A select list holds at
  // most 1664 entries, hence the batches.
  TB_RETURN_IF_ERROR(Exec("SELECT pg_advisory_xact_lock_shared(" + std::to_string(key) + ")"));
  constexpr size_t kLocksPerStatement = 1000;
  for (size_t first = 0; first < parts.size(); first += kLocksPerStatement) {
    const size_t last = std::min(parts.size(), first + kLocksPerStatement);
    std::string sql = "SELECT ";
    for (size_t i = first; i < last; ++i) {
      if (i != first) sql += ", ";
      sql += "pg_advisory_xact_lock(" + std::to_string(surface_part) + ", " +
             std::to_string(parts[i]) + ")";
    }
    TB_RETURN_IF_ERROR(Exec(sql));
  }
  return Status::Ok();
}

Status PgConnection::Commit() {
  Status s = Exec("COMMIT");
  ReleaseRegionWriteLock();
  settled_at_begin_ = 0;
  return s;
}

Status PgConnection::Rollback() {
  Status s = Exec("ROLLBACK");
  ReleaseRegionWriteLock();
  settled_at_begin_ = 0;
  return s;
}

Status PgConnection::BeginSavepoint(std::string_view name) {
  return Exec("SAVEPOINT " + std::string(name));
}
Status PgConnection::ReleaseSavepoint(std::string_view name) {
  return Exec("RELEASE SAVEPOINT " + std::string(name));
}
Status PgConnection::RollbackToSavepoint(std::string_view name) {
  return Exec("ROLLBACK TO SAVEPOINT " + std::string(name));
}

bool PgConnection::InTransaction() const { return PQtransactionStatus(conn_) != PQTRANS_IDLE; }

Result<bool> PgConnection::HasStoreTable() {
  TB_ASSIGN_OR_RETURN(int64_t n, QueryInt("SELECT count(*) FROM pg_tables WHERE schemaname = "
                                          "current_schema() AND tablename = 'tinbase_store'"));
  return n != 0;
}

Result<int64_t> PgConnection::ApplicationId() {
  TB_ASSIGN_OR_RETURN(bool store, HasStoreTable());
  if (!store) return int64_t{0};
  return QueryInt("SELECT application_id FROM tinbase_store");
}

Status PgConnection::SetApplicationId(int32_t id) {
  TB_ASSIGN_OR_RETURN(bool store, HasStoreTable());
  if (!store)
    TB_RETURN_IF_ERROR(Exec(
        "CREATE TABLE tinbase_store(application_id integer NOT NULL, schema_version integer NOT "
        "NULL); INSERT INTO tinbase_store VALUES (0, 0)"));
  return Exec("UPDATE tinbase_store SET application_id = " + std::to_string(id));
}

Result<int64_t> PgConnection::SchemaVersion() {
  TB_ASSIGN_OR_RETURN(bool store, HasStoreTable());
  if (!store) return int64_t{0};
  return QueryInt("SELECT schema_version FROM tinbase_store");
}

Status PgConnection::SetSchemaVersion(int64_t version) {
  return Exec("UPDATE tinbase_store SET schema_version = " + std::to_string(version));
}

Status PgConnection::ConfigureForStore(const StoreSettings& /*settings*/) { return Status::Ok(); }

Result<bool> PgConnection::SetForeignKeys(bool /*on*/) { return true; }

Result<std::unique_ptr<RowStream>> PgConnection::BeginRowStream(std::string_view table_and_columns,
                                                                int columns) {
  TB_ASSIGN_OR_RETURN(std::unique_ptr<PgRowStream> stream,
                      PgRowStream::Begin(conn_, table_and_columns, columns));
  return std::unique_ptr<RowStream>(std::move(stream));
}

}  // namespace tinbase
