// The PostgreSQL module `tinbase` (tinbase.so): the extension's functions written in C++ over the
// tinbase engine (edit_functions.cc, point_functions.cc). This file holds what PostgreSQL asks of
// every module it loads.
// postgres.h must come first.
// clang-format off
extern "C" {
#include "postgres.h"
#include "fmgr.h"
PG_MODULE_MAGIC;
}
// clang-format on
