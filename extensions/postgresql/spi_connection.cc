#include "extensions/postgresql/spi_connection.h"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <functional>

#include "db/postgres/pg_connection.h"

// The server's headers last: their macros (printf, snprintf, ...) would rewrite the standard
// library's; postgres.h must come first among them.
// clang-format off
extern "C" {
#include "postgres.h"
#include "access/xact.h"
#include "catalog/pg_type.h"
#include "executor/spi.h"
#include "fmgr.h"
#include "miscadmin.h"
#include "parser/parse_param.h"
#include "utils/builtins.h"
#include "utils/elog.h"
#include "utils/guc.h"
#include "utils/lsyscache.h"
#include "utils/memutils.h"
#include "utils/resowner.h"
}
// clang-format on

namespace tinbase {
namespace {

// The Status of a caught server error, by its SQLSTATE as StatusFromPg maps libpq's.
Status StatusFromError(const ErrorData* error, std::string_view context) {
  const char* state = unpack_sql_state(error->sqlerrcode);
  std::string message(context);
  message += ": ";
  message += error->message == nullptr ? "unknown error" : error->message;
  const std::string code = state;
  if (code.rfind("40", 0) == 0 || code == "55P03" || code == "57014") return Status::Busy(message);
  if (code.rfind("23", 0) == 0) return Status::Conflict(message);
  if (code == "XX001" || code == "XX002") return Status::Corruption(message);
  if (code.rfind("22", 0) == 0 || code.rfind("42", 0) == 0) return Status::InvalidArgument(message);
  return Status::IOError(message);
}

// Runs `body` (server calls only: no C++ object with a destructor may be alive in its frames)
// under PG_TRY. Returns the caught error as a Status, after `db` has rolled its subtransactions
// back; Ok when `body` returned.
template <typename Body>
Status Guarded(SpiConnection* db, std::string_view context, Body body) {
  if (db != nullptr && db->poison()) return *db->poison();
  MemoryContext before = CurrentMemoryContext;
  ErrorData* volatile caught = nullptr;
  PG_TRY();
  { body(); }
  PG_CATCH();
  {
    MemoryContextSwitchTo(before);
    caught = CopyErrorData();
    FlushErrorState();
  }
  PG_END_TRY();
  if (caught == nullptr) return Status::Ok();
  Status status = StatusFromError(caught, context);
  FreeErrorData(caught);
  return db != nullptr ? db->Poison(status) : status;
}

std::string FormatDouble(double value) {
  // The shortest text that reads back as the same double, as PgStatement sends it.
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text = error == std::errc() ? std::string(buffer, end) : std::string("NaN");
  if (text == "inf") text = "Infinity";
  if (text == "-inf") text = "-Infinity";
  if (text == "nan" || text == "-nan") text = "NaN";
  return text;
}

// What a parse with variable parameters found the types of $1.. to be.
struct VariableParameters {
  Oid* types = nullptr;
  int count = 0;
};

void SetupVariableParameters(ParseState* state, void* arg) {
  auto* parameters = static_cast<VariableParameters*>(arg);
  setup_parse_variable_parameters(state, &parameters->types, &parameters->count);
}

}  // namespace

// ---- SpiStatement ------------------------------------------------------------------------------

SpiStatement::SpiStatement(SpiConnection* db, std::string sql, void* plan,
                           std::vector<unsigned> types)
    : Statement(std::move(sql)), db_(db), plan_(plan), types_(std::move(types)) {}

SpiStatement::~SpiStatement() { Reset(); }

SpiStatement::Parameter& SpiStatement::At(int index) {
  const size_t i = static_cast<size_t>(index - 1);
  if (parameters_.size() <= i) parameters_.resize(i + 1);
  return parameters_[i];
}

SpiStatement& SpiStatement::Bind(int index, int64_t value) {
  Parameter& p = At(index);
  p.kind = Kind::kInt;
  p.i = value;
  return *this;
}

SpiStatement& SpiStatement::Bind(int index, double value) {
  Parameter& p = At(index);
  p.kind = Kind::kDouble;
  p.d = value;
  return *this;
}

SpiStatement& SpiStatement::Bind(int index, std::string_view text) {
  Parameter& p = At(index);
  p.kind = Kind::kText;
  p.text.assign(text);
  return *this;
}

SpiStatement& SpiStatement::BindStaticText(int index, const char* text) {
  return Bind(index, std::string_view(text));
}

SpiStatement& SpiStatement::BindBlob(int index, const void* data, size_t size) {
  Parameter& p = At(index);
  p.kind = Kind::kBlob;
  p.text.assign(static_cast<const char*>(data), size);
  return *this;
}

SpiStatement& SpiStatement::BindNull(int index) {
  At(index).kind = Kind::kNull;
  return *this;
}

std::string SpiStatement::ValueText(int index) const {
  const Parameter& p = parameters_[static_cast<size_t>(index)];
  switch (p.kind) {
    case Kind::kInt:
      return std::to_string(p.i);
    case Kind::kDouble:
      return FormatDouble(p.d);
    default:
      return p.text;
  }
}

Status SpiStatement::Execute() {
  const size_t n = types_.size();
  // Text forms are made before the guarded part, so no std::string is built inside it.
  std::vector<std::string> texts(n);
  for (size_t i = 0; i < n && i < parameters_.size(); ++i)
    texts[i] = ValueText(static_cast<int>(i));
  std::vector<Datum> values(n, Datum(0));
  std::vector<char> nulls(n, 'n');
  nulls.push_back('\0');
  Datum* value_data = values.data();
  char* null_data = nulls.data();
  const Parameter* given = parameters_.data();
  const size_t given_count = parameters_.size();
  const Oid* types = types_.data();
  std::string* text_data = texts.data();
  SPIPlanPtr plan = static_cast<SPIPlanPtr>(plan_);
  int rc = 0;
  int* rc_out = &rc;
  Status status = Guarded(db_, sql().substr(0, 60), [=] {
    for (size_t i = 0; i < n && i < given_count; ++i) {
      const Parameter& p = given[i];
      if (p.kind == Kind::kNull) continue;
      null_data[i] = ' ';
      const Oid type = types[i];
      if (p.kind == Kind::kInt && type == INT8OID) {
        value_data[i] = Int64GetDatum(p.i);
      } else if (p.kind == Kind::kInt && type == INT4OID) {
        value_data[i] = Int32GetDatum(static_cast<int32>(p.i));
      } else if (p.kind == Kind::kDouble && type == FLOAT8OID) {
        value_data[i] = Float8GetDatum(p.d);
      } else if ((p.kind == Kind::kText || p.kind == Kind::kBlob) && type == BYTEAOID) {
        bytea* bytes = static_cast<bytea*>(palloc(VARHDRSZ + p.text.size()));
        SET_VARSIZE(bytes, VARHDRSZ + p.text.size());
        memcpy(VARDATA(bytes), p.text.data(), p.text.size());
        value_data[i] = PointerGetDatum(bytes);
      } else if (type == TEXTOID) {
        value_data[i] = PointerGetDatum(
            cstring_to_text_with_len(text_data[i].data(), static_cast<int>(text_data[i].size())));
      } else {
        Oid input = InvalidOid;
        Oid io_param = InvalidOid;
        getTypeInputInfo(type, &input, &io_param);
        value_data[i] = OidInputFunctionCall(input, text_data[i].data(), io_param, -1);
      }
    }
    *rc_out = SPI_execute_plan(plan, value_data, null_data, false, 0);
  });
  if (!status.ok()) return status;
  if (rc < 0)
    return db_->Poison(Status::IOError(sql().substr(0, 60) + ": " + SPI_result_code_string(rc)));
  rows_ = SPI_tuptable;
  row_count_ = SPI_tuptable == nullptr ? 0 : SPI_processed;
  SPI_tuptable = nullptr;  // ours now: freed by Reset
  depth_ = db_->depth();
  db_->SetChanges(static_cast<int64_t>(SPI_processed));
  db_->Track(this);
  row_ = -1;
  return Status::Ok();
}

Result<bool> SpiStatement::Step() {
  if (db_->poison()) return *db_->poison();
  if (rows_ == nullptr && row_ < 0) {
    TB_RETURN_IF_ERROR(Execute());
  }
  ++row_;
  return static_cast<uint64_t>(row_) < row_count_;
}

Status SpiStatement::Run() {
  Result<bool> r = Step();
  Reset();
  return r.status();
}

void SpiStatement::ForgetRows() {
  rows_ = nullptr;
  row_count_ = 0;
}

void SpiStatement::Reset() {
  if (rows_ != nullptr) {
    auto* rows = static_cast<SPITupleTable*>(rows_);
    // Freeing cannot fail for a table SPI still lists; one it freed is forgotten before.
    SPI_freetuptable(rows);
  }
  db_->Untrack(this);
  rows_ = nullptr;
  row_count_ = 0;
  row_ = -1;
  parameters_.clear();
}

int SpiStatement::ColumnCount() const {
  if (rows_ == nullptr) return 0;
  return static_cast<SPITupleTable*>(rows_)->tupdesc->natts;
}

namespace {

// Column `index` (0-based) of the current row: its datum and type.
struct Cell {
  Datum value = Datum(0);
  bool null = true;
  Oid type = InvalidOid;
};

Cell CellAt(void* rows, int64_t row, int index) {
  Cell cell;
  if (rows == nullptr) return cell;
  auto* table = static_cast<SPITupleTable*>(rows);
  cell.type = SPI_gettypeid(table->tupdesc, index + 1);
  cell.value = SPI_getbinval(table->vals[row], table->tupdesc, index + 1, &cell.null);
  return cell;
}

// The text form of a cell through its type's output function (numeric, dates: rare here).
std::string CellText(void* rows, int64_t row, int index) {
  auto* table = static_cast<SPITupleTable*>(rows);
  char* text = SPI_getvalue(table->vals[row], table->tupdesc, index + 1);
  std::string out = text == nullptr ? "" : text;
  if (text != nullptr) pfree(text);
  return out;
}

}  // namespace

int64_t SpiStatement::ColumnInt(int index) const {
  const Cell c = CellAt(rows_, row_, index);
  if (c.null) return 0;
  switch (c.type) {
    case INT8OID:
      return DatumGetInt64(c.value);
    case INT4OID:
      return DatumGetInt32(c.value);
    case INT2OID:
      return DatumGetInt16(c.value);
    case BOOLOID:
      return DatumGetBool(c.value) ? 1 : 0;
    case FLOAT8OID:
      return static_cast<int64_t>(DatumGetFloat8(c.value));
    default:
      break;
  }
  const std::string text = CellText(rows_, row_, index);
  int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error == std::errc() && end == text.data() + text.size()) return value;
  return static_cast<int64_t>(std::strtod(text.c_str(), nullptr));
}

double SpiStatement::ColumnDouble(int index) const {
  const Cell c = CellAt(rows_, row_, index);
  if (c.null) return 0;
  switch (c.type) {
    case FLOAT8OID:
      return DatumGetFloat8(c.value);
    case FLOAT4OID:
      return DatumGetFloat4(c.value);
    case INT8OID:
      return static_cast<double>(DatumGetInt64(c.value));
    case INT4OID:
      return DatumGetInt32(c.value);
    default:
      return std::strtod(CellText(rows_, row_, index).c_str(), nullptr);
  }
}

std::string SpiStatement::ColumnText(int index) const {
  const Cell c = CellAt(rows_, row_, index);
  if (c.null) return "";
  if (c.type == TEXTOID || c.type == VARCHAROID) {
    auto* t = reinterpret_cast<varlena*>(DatumGetPointer(c.value));
    if (!VARATT_IS_EXTENDED(t)) return std::string(VARDATA_ANY(t), VARSIZE_ANY_EXHDR(t));
  }
  return CellText(rows_, row_, index);
}

bool SpiStatement::ColumnIsNull(int index) const { return CellAt(rows_, row_, index).null; }

const uint8_t* SpiStatement::ColumnBlob(int index, size_t* size) const {
  const Cell c = CellAt(rows_, row_, index);
  *size = 0;
  if (c.null) return nullptr;
  if (c.type != BYTEAOID) {
    static thread_local std::string text;
    text = CellText(rows_, row_, index);
    *size = text.size();
    return reinterpret_cast<const uint8_t*>(text.data());
  }
  // Detoasting reads the table's toast rows: an error there is caught like any other.
  varlena* bytes = nullptr;
  varlena** out = &bytes;
  const Datum value = c.value;
  Status s = Guarded(db_, "reading a blob", [=] {
    *out = pg_detoast_datum_packed(reinterpret_cast<varlena*>(DatumGetPointer(value)));
  });
  if (!s.ok() || bytes == nullptr) return nullptr;
  *size = VARSIZE_ANY_EXHDR(bytes);
  return reinterpret_cast<const uint8_t*>(VARDATA_ANY(bytes));
}

// ---- SpiConnection -----------------------------------------------------------------------------

SpiConnection::SpiConnection(std::string schema, std::string label)
    : schema_(std::move(schema)),
      label_(std::move(label)),
      // The key of PgConnection::BeginWrite, so the extension and the CLI share one writer lock.
      lock_key_(static_cast<int64_t>(std::hash<std::string>()("tinbase/" + schema_) >> 1)) {}

Result<std::unique_ptr<SpiConnection>> SpiConnection::Open(const std::string& schema,
                                                           const std::string& search_path) {
  std::unique_ptr<SpiConnection> db(
      new SpiConnection(schema, "the store in schema '" + schema + "'"));
  TB_RETURN_IF_ERROR(db->BeginSubtransaction());
  db->guard_open_ = true;
  int* level = &db->guc_level_;
  TB_RETURN_IF_ERROR(Guarded(db.get(), "setting search_path", [=] { *level = NewGUCNestLevel(); }));
  TB_RETURN_IF_ERROR(db->SetSearchPath(search_path));
  return db;
}

Status SpiConnection::SetSearchPath(const std::string& path) {
  const char* value = path.c_str();
  return Guarded(this, "setting search_path", [=] {
    (void)set_config_option("search_path", value, PGC_USERSET, PGC_S_SESSION, GUC_ACTION_SAVE, true,
                            0, false);
  });
}

SpiConnection::~SpiConnection() {
  cache_.clear();
  if (guard_open_ && !poison_) (void)Finish(false);
}

Status SpiConnection::Finish(bool ok) {
  cache_.clear();
  if (poison_) return *poison_;
  while (!scopes_.empty()) (void)Pop(false);
  if (guc_level_ > 0) {
    const int level = guc_level_;
    guc_level_ = 0;
    TB_RETURN_IF_ERROR(Guarded(this, "restoring search_path", [=] { AtEOXact_GUC(true, level); }));
  }
  guard_open_ = false;
  return EndSubtransaction(ok);
}

Status SpiConnection::Poison(Status status) {
  // PostgreSQL allows no other server call after a caught error until a subtransaction around
  // it is rolled back: roll back all of ours now.
  for (auto& entry : live_) entry.first->ForgetRows();
  live_.clear();
  while (!saved_.empty()) {
    RollbackAndReleaseCurrentSubTransaction();
    MemoryContextSwitchTo(static_cast<MemoryContext>(saved_.back().first));
    CurrentResourceOwner = static_cast<ResourceOwner>(saved_.back().second);
    saved_.pop_back();
  }
  scopes_.clear();
  guard_open_ = false;
  guc_level_ = 0;  // the rollback restored the setting
  cache_.clear();  // their plans stay valid, but the statements may hold rows of the rollback
  if (!poison_) poison_ = status;
  return *poison_;
}

Status SpiConnection::BeginSubtransaction() {
  if (poison_) return *poison_;
  void* context = CurrentMemoryContext;
  void* owner = CurrentResourceOwner;
  Status s =
      Guarded(nullptr, "beginning a subtransaction", [] { BeginInternalSubTransaction(nullptr); });
  if (!s.ok()) {
    // BeginInternalSubTransaction fails before it changes the state (out of memory): the error
    // is the caller's to raise, with nothing to roll back.
    poison_ = s;
    return s;
  }
  MemoryContextSwitchTo(static_cast<MemoryContext>(context));
  saved_.emplace_back(context, owner);
  return Status::Ok();
}

Status SpiConnection::EndSubtransaction(bool commit) {
  if (poison_) return *poison_;
  if (saved_.empty()) return Status::Ok();
  const int ending = depth();
  for (auto it = live_.begin(); it != live_.end();) {
    SpiStatement* statement = it->first;
    if (statement->depth() < ending) {
      ++it;
    } else if (commit) {
      statement->set_depth(ending - 1);  // its rows now belong to the enclosing level
      ++it;
    } else {
      statement->ForgetRows();  // the rollback frees rows made inside the subtransaction
      it = live_.erase(it);
    }
  }
  const auto [context, owner] = saved_.back();
  Status s = Guarded(this, commit ? "committing" : "rolling back", [=] {
    if (commit) {
      ReleaseCurrentSubTransaction();
    } else {
      RollbackAndReleaseCurrentSubTransaction();
    }
  });
  if (!s.ok()) return s;
  MemoryContextSwitchTo(static_cast<MemoryContext>(context));
  CurrentResourceOwner = static_cast<ResourceOwner>(owner);
  saved_.pop_back();
  return Status::Ok();
}

Status SpiConnection::Pop(bool commit) {
  if (scopes_.empty()) return Status::Ok();
  const ScopeKind kind = scopes_.back();
  scopes_.pop_back();
  if (kind == ScopeKind::kRead) return Status::Ok();
  return EndSubtransaction(commit);
}

Status SpiConnection::Exec(std::string_view sql) {
  const std::string text = PostgresParameters(sql);
  const char* src = text.c_str();
  int rc = 0;
  int* rc_out = &rc;
  TB_RETURN_IF_ERROR(Guarded(this, text.substr(0, 60), [=] {
    *rc_out = SPI_execute(src, false, 0);
    if (SPI_tuptable != nullptr) {
      SPI_freetuptable(SPI_tuptable);
      SPI_tuptable = nullptr;
    }
  }));
  if (rc < 0)
    return Poison(Status::IOError(text.substr(0, 60) + ": " + SPI_result_code_string(rc)));
  SetChanges(static_cast<int64_t>(SPI_processed));
  return Status::Ok();
}

Result<std::unique_ptr<Statement>> SpiConnection::Prepare(std::string_view sql) {
  const std::string text = PostgresParameters(sql);
  const char* src = text.c_str();
  // A first parse learns the parameters' types from their use (as libpq's PQprepare without
  // types does); the kept plan is prepared with them fixed, so a re-plan cannot change them.
  VariableParameters found;
  VariableParameters* found_out = &found;
  SPIPlanPtr plan = nullptr;
  SPIPlanPtr* plan_out = &plan;
  std::vector<unsigned> types;
  TB_RETURN_IF_ERROR(Guarded(this, "preparing " + std::string(sql.substr(0, 60)), [=] {
    SPIPlanPtr probe = SPI_prepare_params(src, SetupVariableParameters, found_out, 0);
    if (probe == nullptr) elog(ERROR, "%s", SPI_result_code_string(SPI_result));
    SPI_freeplan(probe);
  }));
  for (int i = 0; i < found.count; ++i)
    types.push_back(found.types[i] == UNKNOWNOID || found.types[i] == InvalidOid ? TEXTOID
                                                                                 : found.types[i]);
  Oid* type_data = types.data();
  const int count = static_cast<int>(types.size());
  TB_RETURN_IF_ERROR(Guarded(this, "preparing " + std::string(sql.substr(0, 60)), [=] {
    *plan_out = SPI_prepare(src, count, type_data);
    if (*plan_out == nullptr) elog(ERROR, "%s", SPI_result_code_string(SPI_result));
  }));
  return std::unique_ptr<Statement>(
      new SpiStatement(this, std::string(sql), plan, std::move(types)));
}

Result<Statement*> SpiConnection::Cached(std::string_view sql) {
  auto it = cache_.find(std::string(sql));
  if (it != cache_.end()) {
    it->second->Reset();
    return static_cast<Statement*>(it->second.get());
  }
  TB_ASSIGN_OR_RETURN(auto stmt, Prepare(sql));
  auto* raw = static_cast<SpiStatement*>(stmt.release());
  cache_.emplace(std::string(sql), std::unique_ptr<SpiStatement>(raw));
  return static_cast<Statement*>(raw);
}

Result<int64_t> SpiConnection::DataVersion() {
  return QueryInt(
      "SELECT coalesce(max(tx), 0) FROM changes "
      "WHERE xmin IS DISTINCT FROM pg_current_xact_id_if_assigned()::xid");
}

Status SpiConnection::BeginWrite() {
  TB_RETURN_IF_ERROR(BeginSubtransaction());
  scopes_.push_back(ScopeKind::kSubtransaction);
  return Exec("SELECT pg_advisory_xact_lock(" + std::to_string(lock_key_) + ")");
}

Status SpiConnection::BeginRead() {
  if (poison_) return *poison_;
  scopes_.push_back(ScopeKind::kRead);
  return Status::Ok();
}

Status SpiConnection::Commit() { return Pop(true); }
Status SpiConnection::Rollback() { return Pop(false); }

Status SpiConnection::BeginSavepoint(std::string_view /*name*/) {
  TB_RETURN_IF_ERROR(BeginSubtransaction());
  scopes_.push_back(ScopeKind::kSubtransaction);
  return Status::Ok();
}

// Savepoints nest strictly (db/sql/transaction.h's Savepoint is a scope), so the innermost
// subtransaction is the named one.
Status SpiConnection::ReleaseSavepoint(std::string_view /*name*/) { return Pop(true); }

Status SpiConnection::RollbackToSavepoint(std::string_view name) {
  TB_RETURN_IF_ERROR(Pop(false));
  return BeginSavepoint(name);
}

Result<bool> SpiConnection::HasStoreTable() {
  TB_ASSIGN_OR_RETURN(int64_t n, QueryInt("SELECT count(*) FROM pg_tables WHERE schemaname = "
                                          "current_schema() AND tablename = 'tinbase_store'"));
  return n != 0;
}

Result<int64_t> SpiConnection::ApplicationId() {
  TB_ASSIGN_OR_RETURN(bool store, HasStoreTable());
  if (!store) return int64_t{0};
  return QueryInt("SELECT application_id FROM tinbase_store");
}

Status SpiConnection::SetApplicationId(int32_t /*id*/) {
  return Status::InvalidArgument("the extension does not make stores: CREATE EXTENSION does");
}

Result<int64_t> SpiConnection::SchemaVersion() {
  TB_ASSIGN_OR_RETURN(bool store, HasStoreTable());
  if (!store) return int64_t{0};
  return QueryInt("SELECT schema_version FROM tinbase_store");
}

Status SpiConnection::SetSchemaVersion(int64_t /*version*/) {
  return Status::InvalidArgument("the extension does not migrate stores: ALTER EXTENSION does");
}

}  // namespace tinbase
