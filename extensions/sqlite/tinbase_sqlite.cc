// libtinbase_sqlite: tinbase's read functions as an SQLite loadable extension, so any SQLite
// client can ask a store file for its TINs in SQL (docs/cli.md, "SQL functions in SQLite"):
//
//   .load ./libtinbase_sqlite
//   SELECT tinbase_z('terrain', x, y) FROM wells;
//
// tinbase_z, tinbase_locate, tinbase_tag (NULL outside the surface), tinbase_neighbours,
// tinbase_check and tinbase_profile answer from the library (LocatePoint's walk, NeighboursOf,
// CheckStore, ProfileAlong), never from SQL of their own.
//
// Ownership: each connection that loads the extension gets one StoreHandle, shared by its
// functions and freed with the connection; it opens a tinbase Store read-only on the file of the
// connection's "main" database on first use. The functions therefore read what is committed in
// that file, not the calling connection's own uncommitted writes. The point functions keep a
// SurfaceCursor (the surface, a read snapshot and a PointLocator) as SQLite auxiliary data of
// their surface argument: while that argument is a constant, the cursor lives as long as the
// statement runs, so a column of points sorted in space walks from one answer to the next, and
// every row of one statement reads the same snapshot.
// Thread-safety: SQLite calls a connection's functions one at a time; nothing is shared between
// connections.
#include <sqlite3ext.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/predicates.h"
#include "core/query/point_input.h"
#include "db/integrity_check.h"
#include "db/integrity_check_json.h"
#include "db/point_locator.h"
#include "db/query/profile.h"
#include "db/query/profile_json.h"
#include "db/query/topology.h"
#include "db/store.h"
#include "db/surface_store.h"

SQLITE_EXTENSION_INIT1

namespace tinbase {
namespace {

// The tinbase Store of one connection's main database, opened on first use.
class StoreHandle {
 public:
  explicit StoreHandle(sqlite3* db) : db_(db) {}

  // The store, or the reason it cannot be opened (an in-memory database, a file that is not a
  // tinbase store, one made by a newer tinbase).
  Result<Store*> Get() {
    if (store_ != nullptr) return store_.get();
    const char* file = sqlite3_db_filename(db_, "main");
    if (file == nullptr || file[0] == '\0') {
      return Status::InvalidArgument(
          "the main database is not a file (tinbase opens the store file it is in)");
    }
    TB_ASSIGN_OR_RETURN(store_, Store::Open(file, Store::Access::kReadOnly));
    return store_.get();
  }

  // The read snapshot every cursor of the connection shares while one is alive: SQLite cannot
  // nest read transactions on the store's connection, and two functions of one statement must
  // not read two states of the store.
  Result<std::shared_ptr<ReadSnapshot>> Snapshot() {
    if (auto alive = snapshot_.lock()) return alive;
    TB_ASSIGN_OR_RETURN(Store * store, Get());
    TB_ASSIGN_OR_RETURN(std::unique_ptr<ReadSnapshot> begun, ReadSnapshot::Begin(*store));
    std::shared_ptr<ReadSnapshot> shared = std::move(begun);
    snapshot_ = shared;
    return shared;
  }

 private:
  sqlite3* db_;
  std::unique_ptr<Store> store_;
  std::weak_ptr<ReadSnapshot> snapshot_;
};

// What one function keeps between the rows of a statement (see the file comment).
struct SurfaceCursor {
  std::shared_ptr<StoreHandle> handle;  // outlives the snapshot and the locator
  std::shared_ptr<ReadSnapshot> snapshot;
  Store* store = nullptr;
  SurfaceInfo surface;
  std::unique_ptr<PointLocator> locator;  // made on first use
};

// The function's user data: the connection's handle (one copy per registered function; SQLite
// destroys each when the connection closes).
using HandleRef = std::shared_ptr<StoreHandle>;

void ResultError(sqlite3_context* context, const std::string& function,
                 const std::string& message) {
  const std::string text = function + ": " + message;
  sqlite3_result_error(context, text.c_str(), static_cast<int>(text.size()));
}

const char* TypeName(int type) {
  switch (type) {
    case SQLITE_INTEGER:
      return "an integer";
    case SQLITE_FLOAT:
      return "a real";
    case SQLITE_TEXT:
      return "text";
    case SQLITE_BLOB:
      return "a blob";
    default:
      return "NULL";
  }
}

// The text of argument `index` (0-based), or an error naming the function and the argument.
std::optional<std::string> TextArgument(sqlite3_context* context, const char* function,
                                        sqlite3_value** argv, int index, const char* name) {
  if (sqlite3_value_type(argv[index]) != SQLITE_TEXT) {
    ResultError(context, function,
                "argument " + std::to_string(index + 1) + " (" + name + ") must be text, got " +
                    TypeName(sqlite3_value_type(argv[index])));
    return std::nullopt;
  }
  const auto* text = reinterpret_cast<const char*>(sqlite3_value_text(argv[index]));
  return std::string(text, static_cast<size_t>(sqlite3_value_bytes(argv[index])));
}

// A finite coordinate from argument `index`: an integer, a real, or text that reads as one.
// Sets an error naming the function and argument otherwise. REQUIRES: the argument is not NULL.
std::optional<double> CoordinateArgument(sqlite3_context* context, const char* function,
                                         sqlite3_value** argv, int index, const char* name) {
  const int type = sqlite3_value_numeric_type(argv[index]);
  if (type != SQLITE_INTEGER && type != SQLITE_FLOAT) {
    std::string shown = TypeName(sqlite3_value_type(argv[index]));
    if (sqlite3_value_type(argv[index]) == SQLITE_TEXT) {
      shown +=
          " '" + std::string(reinterpret_cast<const char*>(sqlite3_value_text(argv[index]))) + "'";
    }
    ResultError(
        context, function,
        "argument " + std::to_string(index + 1) + " (" + name + ") must be a number, got " + shown);
    return std::nullopt;
  }
  const double value = sqlite3_value_double(argv[index]);
  if (!std::isfinite(value)) {
    ResultError(context, function,
                "argument " + std::to_string(index + 1) + " (" + name + ") must be finite, got " +
                    (std::isnan(value) ? std::string("NaN")
                     : value > 0       ? "+Inf"
                                       : "-Inf"));
    return std::nullopt;
  }
  return value;
}

// The cursor of the statement's surface argument (argument 1): the one kept from an earlier row
// when SQLite kept it, else a new one. Null after setting an error.
std::unique_ptr<SurfaceCursor> OpenCursor(sqlite3_context* context, const char* function,
                                          sqlite3_value** argv) {
  std::optional<std::string> name = TextArgument(context, function, argv, 0, "surface");
  if (!name) return nullptr;
  auto cursor = std::make_unique<SurfaceCursor>();
  cursor->handle = *static_cast<HandleRef*>(sqlite3_user_data(context));
  auto fail = [&](const Status& status) {
    ResultError(context, function, status.message());
    return nullptr;
  };
  auto store = cursor->handle->Get();
  if (!store.ok()) return fail(store.status());
  cursor->store = *store;
  auto snapshot = cursor->handle->Snapshot();
  if (!snapshot.ok()) return fail(snapshot.status());
  cursor->snapshot = std::move(*snapshot);
  auto surface = SurfaceStore(*cursor->store).Find(*name);
  if (!surface.ok()) return fail(surface.status());
  cursor->surface = std::move(*surface);
  return cursor;
}

void DeleteCursor(void* cursor) { delete static_cast<SurfaceCursor*>(cursor); }

// Runs `answer(cursor)` with the statement's cursor, then hands the cursor back to SQLite to keep
// for the next row. SQLite may free auxiliary data at any time after set_auxdata (even inside
// it), so the cursor is used first and handed over last.
template <typename Answer>
void WithCursor(sqlite3_context* context, const char* function, sqlite3_value** argv,
                Answer answer) {
  auto* kept = static_cast<SurfaceCursor*>(sqlite3_get_auxdata(context, 0));
  if (kept != nullptr) {
    answer(*kept);
    return;
  }
  std::unique_ptr<SurfaceCursor> cursor = OpenCursor(context, function, argv);
  if (cursor == nullptr) return;
  answer(*cursor);
  sqlite3_set_auxdata(context, 0, cursor.release(), DeleteCursor);
}

// tinbase_z / tinbase_locate / tinbase_tag (surface, x, y): what LocatePoint says about the
// point; NULL outside the surface, or when x or y is NULL.
enum class PointAnswer { kZ, kTriangle, kTag };

template <PointAnswer kAnswer>
void PointFunction(sqlite3_context* context, int argc, sqlite3_value** argv) {
  (void)argc;
  constexpr const char* kFunction = kAnswer == PointAnswer::kZ          ? "tinbase_z"
                                    : kAnswer == PointAnswer::kTriangle ? "tinbase_locate"
                                                                        : "tinbase_tag";
  if (sqlite3_value_type(argv[1]) == SQLITE_NULL || sqlite3_value_type(argv[2]) == SQLITE_NULL) {
    // Still check the surface, so a misspelt name fails on a table whose first row has no point.
    WithCursor(context, kFunction, argv, [&](SurfaceCursor&) { sqlite3_result_null(context); });
    return;
  }
  const std::optional<double> x = CoordinateArgument(context, kFunction, argv, 1, "x");
  if (!x) return;
  const std::optional<double> y = CoordinateArgument(context, kFunction, argv, 2, "y");
  if (!y) return;
  WithCursor(context, kFunction, argv, [&](SurfaceCursor& cursor) {
    if (cursor.locator == nullptr) {
      cursor.locator = std::make_unique<PointLocator>(*cursor.store, cursor.surface);
    }
    Result<Location> where = kAnswer == PointAnswer::kTag ? cursor.locator->Locate(*x, *y)
                                                          : cursor.locator->LocateTriangle(*x, *y);
    if (!where.ok()) {
      if (where.status().code() == StatusCode::kNotFound) {
        sqlite3_result_null(context);
      } else {
        ResultError(context, kFunction, where.status().message());
      }
      return;
    }
    if constexpr (kAnswer == PointAnswer::kZ) {
      sqlite3_result_double(context, where->z);
    } else if constexpr (kAnswer == PointAnswer::kTriangle) {
      sqlite3_result_int64(context, where->triangle);
    } else if (where->tag) {
      sqlite3_result_text(context, where->tag->c_str(), static_cast<int>(where->tag->size()),
                          SQLITE_TRANSIENT);
    } else {
      sqlite3_result_null(context);
    }
  });
}

void ResultJson(sqlite3_context* context, const nlohmann::json& json) {
  const std::string text = json.dump();
  sqlite3_result_text(context, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  sqlite3_result_subtype(context, static_cast<unsigned>('J'));  // JSON, as SQLite's json1 marks it
}

// tinbase_neighbours(surface, triangle): [n0, n1, n2], the triangle across the edge opposite
// each corner (null on the boundary), as NeighboursOf orders them.
void NeighboursFunction(sqlite3_context* context, int argc, sqlite3_value** argv) {
  (void)argc;
  constexpr const char* kFunction = "tinbase_neighbours";
  if (sqlite3_value_type(argv[1]) == SQLITE_NULL) {
    WithCursor(context, kFunction, argv, [&](SurfaceCursor&) { sqlite3_result_null(context); });
    return;
  }
  if (sqlite3_value_numeric_type(argv[1]) != SQLITE_INTEGER) {
    ResultError(context, kFunction,
                std::string("argument 2 (triangle) must be an integer triangle id, got ") +
                    TypeName(sqlite3_value_type(argv[1])));
    return;
  }
  const int64_t triangle = sqlite3_value_int64(argv[1]);
  WithCursor(context, kFunction, argv, [&](SurfaceCursor& cursor) {
    auto around = NeighboursOf(*cursor.store, cursor.surface, triangle);
    if (!around.ok()) {
      ResultError(context, kFunction, around.status().message());
      return;
    }
    nlohmann::json ids = nlohmann::json::array();
    for (const SharedEdge& edge : around->edges) {
      ids.push_back(edge.neighbour ? nlohmann::json(*edge.neighbour) : nlohmann::json(nullptr));
    }
    ResultJson(context, ids);
  });
}

// tinbase_check(surface [, full]): what `tinbase check --json --surface S [--full]` prints
// (db/integrity_check_json.h).
void CheckFunction(sqlite3_context* context, int argc, sqlite3_value** argv) {
  constexpr const char* kFunction = "tinbase_check";
  std::optional<std::string> name = TextArgument(context, kFunction, argv, 0, "surface");
  if (!name) return;
  CheckOptions options;
  options.surface = *name;
  if (argc > 1) {
    if (sqlite3_value_numeric_type(argv[1]) != SQLITE_INTEGER) {
      ResultError(context, kFunction,
                  std::string("argument 2 (full) must be 0 or 1, got ") +
                      TypeName(sqlite3_value_type(argv[1])));
      return;
    }
    options.full = sqlite3_value_int64(argv[1]) != 0;
  }
  HandleRef handle = *static_cast<HandleRef*>(sqlite3_user_data(context));
  auto store = handle->Get();
  if (!store.ok()) return ResultError(context, kFunction, store.status().message());
  auto problems = CheckStore(**store, options);
  if (!problems.ok()) return ResultError(context, kFunction, problems.status().message());
  ResultJson(context, CheckJson(*problems));
}

// A profile line from SQL: WKT "LINESTRING (x y, x y, ...)" or the CLI's "x,y x,y ...".
Result<std::vector<Point2>> ParseLine(const std::string& text) {
  const size_t open = text.find('(');
  std::string head = text.substr(0, open == std::string::npos ? 0 : open);
  for (char& c : head) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (open == std::string::npos || head.find("LINESTRING") == std::string::npos) {
    return ParsePointList(text, "argument 2 (line)");
  }
  const size_t close = text.rfind(')');
  if (close == std::string::npos || close < open) {
    return Status::InvalidArgument("argument 2 (line) '" + text +
                                   "': the LINESTRING is not closed");
  }
  // "x y, x y" becomes "x,y;x,y", the point list ParsePointList reads.
  std::string list;
  bool in_number = false;
  bool after_x = false;
  for (size_t i = open + 1; i < close; ++i) {
    const char c = text[i];
    if (c == ',') {
      list += ';';
      in_number = after_x = false;
    } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      if (in_number && !after_x) {
        after_x = true;
        list += ',';
      }
      in_number = false;
    } else {
      in_number = true;
      list += c;
    }
  }
  return ParsePointList(list, "argument 2 (line) '" + text + "'");
}

// tinbase_profile(surface, line): `tinbase profile --json` (db/query/profile_json.h).
void ProfileFunction(sqlite3_context* context, int argc, sqlite3_value** argv) {
  (void)argc;
  constexpr const char* kFunction = "tinbase_profile";
  std::optional<std::string> text = TextArgument(context, kFunction, argv, 1, "line");
  if (!text) return;
  auto line = ParseLine(*text);
  if (!line.ok()) return ResultError(context, kFunction, line.status().message());
  WithCursor(context, kFunction, argv, [&](SurfaceCursor& cursor) {
    auto profile = ProfileAlong(*cursor.store, cursor.surface, *line);
    if (!profile.ok()) return ResultError(context, kFunction, profile.status().message());
    ResultJson(context, ProfileJson(*profile, cursor.surface.name));
  });
}

void DeleteHandleRef(void* ref) { delete static_cast<HandleRef*>(ref); }

int Register(sqlite3* db, char** error) {
#ifdef SQLITE_RESULT_SUBTYPE
  // SQLite 3.45 and later want functions that set a subtype (the JSON ones) to say so.
  constexpr int kJson = SQLITE_RESULT_SUBTYPE;
#else
  constexpr int kJson = 0;
#endif
  struct Function {
    const char* name;
    int arguments;
    void (*call)(sqlite3_context*, int, sqlite3_value**);
    int flags;
  };
  const Function functions[] = {
      {"tinbase_z", 3, PointFunction<PointAnswer::kZ>, 0},
      {"tinbase_locate", 3, PointFunction<PointAnswer::kTriangle>, 0},
      {"tinbase_tag", 3, PointFunction<PointAnswer::kTag>, 0},
      {"tinbase_neighbours", 2, NeighboursFunction, kJson},
      {"tinbase_check", 1, CheckFunction, kJson},
      {"tinbase_check", 2, CheckFunction, kJson},
      {"tinbase_profile", 2, ProfileFunction, kJson},
  };
  auto handle = std::make_shared<StoreHandle>(db);
  for (const Function& f : functions) {
    // Not SQLITE_DETERMINISTIC: the answers follow the store file, which other connections change.
    const int rc = sqlite3_create_function_v2(db, f.name, f.arguments, SQLITE_UTF8 | f.flags,
                                              new HandleRef(handle), f.call, nullptr, nullptr,
                                              DeleteHandleRef);
    if (rc != SQLITE_OK) {
      // SQLite has already called DeleteHandleRef on the user data of the failed registration.
      *error =
          sqlite3_mprintf("tinbase_sqlite: cannot register %s: %s", f.name, sqlite3_errmsg(db));
      return rc;
    }
  }
  return SQLITE_OK;
}

}  // namespace
}  // namespace tinbase

// The entry points. SQLite's `.load FILE` looks up `sqlite3_extension_init` first, and dlsym
// finds that name in the module's dependencies too: libgdal exports one (GDAL's own SQLite
// extension), which would be loaded instead of this one. So the module defines it itself (dlsym
// searches the module before its dependencies), as well as the name SQLite derives from the file
// name (the lower-case letters of "libtinbase_sqlite" without "lib") and the module's own name.
extern "C" int sqlite3_tinbasesqlite_init(sqlite3* db, char** error,
                                          const sqlite3_api_routines* api) {
  SQLITE_EXTENSION_INIT2(api);
  return tinbase::Register(db, error);
}

extern "C" int sqlite3_tinbase_sqlite_init(sqlite3* db, char** error,
                                           const sqlite3_api_routines* api) {
  return sqlite3_tinbasesqlite_init(db, error, api);
}

extern "C" int sqlite3_extension_init(sqlite3* db, char** error, const sqlite3_api_routines* api) {
  return sqlite3_tinbasesqlite_init(db, error, api);
}
