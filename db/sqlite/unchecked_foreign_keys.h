// Transitional: moved to db/sql/unchecked_foreign_keys.h.
#pragma once

#include "db/sql/unchecked_foreign_keys.h"
