// Transitional: moved to db/sql/bulk_write.h.
#pragma once

#include "db/sql/bulk_write.h"
