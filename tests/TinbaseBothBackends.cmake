# Which tests (or which of their cases) run on SQLite only, and why (tests/CMakeLists.txt runs
# every other test that takes its stores from tests/support/store_target.h on both backends).
# Each entry says why; nearly all are about SQLite by nature: its files, its SQL dialect in the
# test's own statements, its data_version, its file permissions.

# Whole test binaries.
set(TINBASE_SQLITE_ONLY_TESTS
  # A PostgreSQL test already: it compares a PostgreSQL store with an SQLite file.
  softline_postgres_test
  # Not by nature, but for now: its store is made by `tinbase demo`, which writes an SQLite file
  # only (the GeoPackage export on PostgreSQL is tested by gpkg_export_test and
  # store_geopackage_test). It takes no StoreTarget, so it is listed here for the record.
  gpkg_cli_test
  # The SQLite store file is itself a GeoPackage, read by GDAL (no StoreTarget; for the record).
  store_geopackage_test
  # For now: its surface signature (tests/db/history/surface_signature.h) is SQLite SQL (printf,
  # hex); it takes no StoreTarget yet. Listed for the record. revert_property_test compares with
  # the same signature.
  revert_test
  revert_property_test
  # Hostile input against the store file and the serve process on a file: paths, permissions,
  # truncated and overwritten store files, /dev/null.
  hostile_inputs_test
  hostile_service_test
  # Damages DEM block rows with SQLite's SQL (changes(), zeroblob).
  dem_corruption_test
)

# Test cases, by GoogleTest pattern, per binary.
set(TINBASE_SQLITE_ONLY_dem_store_test
  # Damages a block's bytes in the file, and fakes a schema-2 file store.
  "DemStore.DamagedBlock*" "DemStore.Migration0003*")
set(TINBASE_SQLITE_ONLY_dem_mosaic_test
  # Reads SQLite's data_version between sheets.
  "Mosaic.SheetsAddedOneByOne*")
set(TINBASE_SQLITE_ONLY_surface_store_test
  # Breaks references with SQLite's foreign-key pragma off.
  "*LoadNamesBrokenReferences*")
set(TINBASE_SQLITE_ONLY_update_engine_each_test
  # Count row reads through SQLite's page cache, and a second writer seen by data_version.
  "*EachLoadOverMuchOfTheSurfaceReadsItOnce" "*EachDropsTheMeshRowsWhenAnotherWriterCommits")
set(TINBASE_SQLITE_ONLY_update_engine_whole_surface_test
  # Reads a whole surface row by row to show the cache: slow over a socket, the same code on both.
  "*ManyFeaturesOverMostOfTheSurfaceReplaceItWhole")
set(TINBASE_SQLITE_ONLY_hostile_cli_test
  # File permissions on the store file and its folder, and SQLite's user_version.
  "*StoreInUnreadableDirectoryIsPermissionDenied" "*ReadOnlyStoreAndReadOnlyDirectorySayPermission"
  "*BrokenUserVersionIsReportedAsDamageNotAsMigrationSql")
set(TINBASE_SQLITE_ONLY_feature_mode_row_test
  # Writes a bad mode past the CHECK constraint with SQLite's ignore_check_constraints pragma.
  "*AnUnknownModeInARowIsCorruptionNamingTheFeature")
