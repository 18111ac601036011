// Transitional: the old name of the connection, until the renaming commit replaces every use.
#pragma once

#include "db/sqlite/sqlite_connection.h"

namespace tinbase {
using SqliteDb = SqliteConnection;
}  // namespace tinbase
