#include "db/postgres/pg_copy.h"

#include <libpq-fe.h>

#include "db/postgres/pg_connection.h"

namespace tinbase {

namespace {

// Rows are sent in chunks of about this size: large enough that the per-call cost of libpq and
// the socket is small against the bytes, small enough to stay in cache.
constexpr size_t kChunkBytes = size_t{1} << 20;

constexpr char kNull[] = "\\N";

// libpq's last message on `conn`, without its closing newline.
std::string LastError(pg_conn* conn) {
  std::string text = PQerrorMessage(conn);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

}  // namespace

void AppendCopyText(std::string_view value, std::string* out) {
  for (const char c : value) {
    switch (c) {
      case '\\':
        *out += "\\\\";
        break;
      case '\t':
        *out += "\\t";
        break;
      case '\n':
        *out += "\\n";
        break;
      case '\r':
        *out += "\\r";
        break;
      default:
        *out += c;
    }
  }
}

void AppendCopyBytea(const void* bytes, size_t size, std::string* out) {
  static constexpr char kHex[] = "0123456789abcdef";
  const auto* b = static_cast<const unsigned char*>(bytes);
  out->reserve(out->size() + 3 + 2 * size);
  *out += "\\\\x";  // bytea's hex prefix \x, its backslash escaped for COPY
  for (size_t i = 0; i < size; ++i) {
    *out += kHex[b[i] >> 4];
    *out += kHex[b[i] & 15];
  }
}

PgRowStream::PgRowStream(pg_conn* conn, std::string sql, int columns)
    : RowStream(std::move(sql)), conn_(conn), fields_(static_cast<size_t>(columns), kNull) {
  buffer_.reserve(kChunkBytes + 4096);
}

Result<std::unique_ptr<PgRowStream>> PgRowStream::Begin(pg_conn* conn,
                                                        std::string_view table_and_columns,
                                                        int columns) {
  std::string sql = "COPY " + std::string(table_and_columns) + " FROM STDIN";
  PGresult* started = PQexec(conn, sql.c_str());
  if (PQresultStatus(started) != PGRES_COPY_IN) {
    Status s = StatusFromPg(started, conn, sql);
    PQclear(started);
    // A result of another kind than an error (none is expected) still must not pass as a stream.
    return s.ok() ? Status::IOError(sql + ": the server did not start the copy") : s;
  }
  PQclear(started);
  return std::unique_ptr<PgRowStream>(new PgRowStream(conn, std::move(sql), columns));
}

PgRowStream::~PgRowStream() {
  if (!open_) return;
  PQputCopyEnd(conn_, "tinbase: row stream abandoned");
  while (PGresult* r = PQgetResult(conn_)) PQclear(r);
}

std::string& PgRowStream::At(int index) { return fields_.at(static_cast<size_t>(index - 1)); }

PgRowStream& PgRowStream::Bind(int index, int64_t value) {
  At(index) = std::to_string(value);
  return *this;
}

PgRowStream& PgRowStream::Bind(int index, double value) {
  At(index) = PostgresFloatText(value);
  return *this;
}

PgRowStream& PgRowStream::Bind(int index, std::string_view text) {
  std::string& field = At(index);
  field.clear();
  AppendCopyText(text, &field);
  return *this;
}

PgRowStream& PgRowStream::BindStaticText(int index, const char* text) {
  return Bind(index, std::string_view(text));
}

PgRowStream& PgRowStream::BindBlob(int index, const void* data, size_t size) {
  std::string& field = At(index);
  field.clear();
  AppendCopyBytea(data, size, &field);
  return *this;
}

PgRowStream& PgRowStream::BindNull(int index) {
  At(index) = kNull;
  return *this;
}

Result<bool> PgRowStream::Step() {
  TB_RETURN_IF_ERROR(Run());
  return false;
}

Status PgRowStream::Run() {
  if (!open_) return Status::InvalidArgument(sql() + ": a row after the stream ended");
  for (size_t i = 0; i < fields_.size(); ++i) {
    if (i != 0) buffer_ += '\t';
    buffer_ += fields_[i];
  }
  buffer_ += '\n';
  return buffer_.size() >= kChunkBytes ? Send() : Status::Ok();
}

Status PgRowStream::Send() {
  if (buffer_.empty()) return Status::Ok();
  // libpq refuses more data once the server has reported an error (a row broke a constraint):
  // ending the copy then collects that error, which says more than the refusal.
  if (PQputCopyData(conn_, buffer_.data(), static_cast<int>(buffer_.size())) != 1)
    return End(Status::IOError(sql() + ": " + LastError(conn_)));
  buffer_.clear();
  return Status::Ok();
}

Status PgRowStream::Finish() {
  if (!open_) return Status::Ok();
  Status sent = Send();
  return open_ ? End(sent) : sent;
}

Status PgRowStream::End(Status sent) {
  open_ = false;
  // A failed send tells the server to drop the rows; either way the connection leaves COPY mode.
  if (PQputCopyEnd(conn_, sent.ok() ? nullptr : "tinbase: sending rows failed") != 1 && sent.ok())
    sent = Status::IOError(sql() + ": " + LastError(conn_));
  Status ended = Status::Ok();
  while (PGresult* r = PQgetResult(conn_)) {
    if (ended.ok()) ended = StatusFromPg(r, conn_, sql());
    PQclear(r);
  }
  return ended.ok() ? sent : ended;
}

}  // namespace tinbase
