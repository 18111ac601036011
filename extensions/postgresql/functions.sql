-- The SQL functions of the PostgreSQL extension `tinbase` (extensions/postgresql/CMakeLists.txt
-- appends this file to schema/postgresql.sql). They read the store's tables in the caller's
-- transaction, so they see its own uncommitted edits and a ROLLBACK undoes whatever it did.
-- Each pins search_path to the store's schema and PostGIS's (SET search_path FROM CURRENT: the
-- path CREATE EXTENSION ran the script with), so they answer the same from any search_path.
--
-- Every tinbase_* function but the small SQL helpers is C++ in the module tinbase.so
-- (extensions/postgresql/*.cc): the engine itself, run through an SPI connection in the caller's
-- transaction, with CGAL's exact predicates, giving the CLI's answers.

-- The functions of the migrations (the id triggers, tinbase_srid of the PostGIS views) name the
-- store's tables unqualified, for the CLI's search_path; pinned here too, the views and the
-- triggers work from any search_path.
DO $$
DECLARE
  f regprocedure;
BEGIN
  FOR f IN SELECT p.oid FROM pg_proc p
           WHERE p.pronamespace = current_schema()::regnamespace AND p.proconfig IS NULL LOOP
    EXECUTE format('ALTER FUNCTION %s SET search_path FROM CURRENT', f);
  END LOOP;
END $$;

-- The path CREATE EXTENSION ran with (SET search_path FROM CURRENT gives it back): the C++
-- functions of the module set it for their own queries, as the SQL ones pin it.
CREATE FUNCTION tinbase_search_path() RETURNS text
LANGUAGE sql STABLE SET search_path FROM CURRENT AS $$ SELECT current_setting('search_path') $$;

-- The id of the triangle of surface `surface_name` that holds (px, py), visible or not; NULL
-- outside the surface. An error when the surface does not exist. C++ (point_functions.cc): the
-- walk of tinbase's bulk location over the surface held in memory, exact as the CLI's.
CREATE FUNCTION tinbase_locate(surface_name text, px double precision, py double precision)
RETURNS bigint LANGUAGE c STABLE STRICT AS 'MODULE_PATHNAME', 'tinbase_locate_c';

-- The height of surface `surface_name` at (px, py): the plane of the triangle that holds the
-- point, visible or not (as `tinbase locate`); NULL outside the surface. C++, as tinbase_locate.
CREATE FUNCTION tinbase_z(surface_name text, px double precision, py double precision)
RETURNS double precision LANGUAGE c STABLE STRICT AS 'MODULE_PATHNAME', 'tinbase_z_c';

-- Adds `geom` (a Polygon or MultiPolygon for clip, erase, fill, replace; a LineString or
-- MultiLineString for breakline, softline; in the store's CRS, or SRID 0) to surface
-- `surface_name` as `tinbase polygon add --mode MODE --tag TAG` does: one local edit, in the
-- caller's transaction (a ROLLBACK undoes it), with its `changes` row. Returns the feature's id.
-- `tag` may be NULL. Bad input (unknown surface or mode, an invalid polygon, a coordinate that is
-- not a number) is an error naming the argument, ring and vertex; nothing is written then.
CREATE FUNCTION tinbase_add_polygon_wkb(surface_name text, wkb bytea, srid integer, mode text,
                                        tag text)
RETURNS bigint LANGUAGE c VOLATILE AS 'MODULE_PATHNAME', 'tinbase_add_polygon_wkb';
CREATE FUNCTION tinbase_add_polygon(surface_name text, geom geometry, mode text,
                                    tag text DEFAULT NULL)
RETURNS bigint LANGUAGE sql VOLATILE SET search_path FROM CURRENT AS $$
  SELECT tinbase_add_polygon_wkb(surface_name, ST_AsBinary(geom), ST_SRID(geom), mode, tag)
$$;

-- Removes feature `feature` of surface `surface_name` as `tinbase polygon remove` does, in the
-- caller's transaction. Returns the number of the edit's `changes` row. An error when the surface
-- has no such feature.
CREATE FUNCTION tinbase_remove_feature(surface_name text, feature bigint)
RETURNS bigint LANGUAGE c VOLATILE STRICT AS 'MODULE_PATHNAME', 'tinbase_remove_feature';

CREATE FUNCTION tinbase_locate(surface_name text, point geometry)
RETURNS bigint LANGUAGE sql STABLE STRICT SET search_path FROM CURRENT AS $$
  SELECT tinbase_locate(surface_name, ST_X(point), ST_Y(point))
$$;

-- The triangles across the edges of `triangle` (of surface `surface_name`), in edge order; none
-- on the boundary. An error when the triangle is not one of the surface's. C++
-- (set_functions.cc): the library's NeighboursOf.
CREATE FUNCTION tinbase_neighbours(surface_name text, triangle bigint)
RETURNS SETOF bigint LANGUAGE c STABLE STRICT ROWS 3 AS 'MODULE_PATHNAME', 'tinbase_neighbours_c';

-- The surface along `line` (a LineString in the store's CRS), as `tinbase profile` gives it: one
-- row per station (`start`, every `edge` crossing, each `vertex` passed, each `bend`, `end`) with
-- its plan distance along the line, x, y and z, and the triangle, visibility and tag of the
-- stretch that begins there (none at the end). A line that leaves the surface, or whose first
-- point is outside it, is refused naming the place, as by the CLI. C++ (set_functions.cc): the
-- library's ProfileAlong, exact as the CLI's.
CREATE FUNCTION tinbase_profile_wkb(surface_name text, line bytea)
RETURNS TABLE(distance double precision, x double precision, y double precision,
              z double precision, kind text, triangle bigint, visible boolean, tag text)
LANGUAGE c STABLE STRICT AS 'MODULE_PATHNAME', 'tinbase_profile_wkb';
CREATE FUNCTION tinbase_profile(surface_name text, line geometry)
RETURNS TABLE(distance double precision, x double precision, y double precision,
              z double precision, kind text, triangle bigint, visible boolean, tag text)
LANGUAGE sql STABLE STRICT SET search_path FROM CURRENT AS $$
  SELECT * FROM tinbase_profile_wkb(surface_name, ST_AsBinary(line))
$$;

-- The problems `tinbase check --surface surface_name` reports (every invariant but those of
-- --full), with its codes and words: the code, the triangle (NULL for a problem of no one
-- triangle) and the words after "surface 'name', triangle N: ". None for a sound surface. C++
-- (set_functions.cc): the library's CheckStore, exact as the CLI's.
CREATE FUNCTION tinbase_check(surface_name text)
RETURNS TABLE(problem text, triangle_id bigint, detail text)
LANGUAGE c STABLE STRICT AS 'MODULE_PATHNAME', 'tinbase_check_c';

-- pg_dump keeps the rows of a store made by the extension: its tables belong to the extension,
-- whose objects pg_dump otherwise leaves to CREATE EXTENSION. Every table of the script is
-- marked, less the rows this script makes itself (a restore runs it again before it loads the
-- rows): tinbase_store's one row and the rows of meta the migrations wrote.
DO $$
DECLARE
  name text;
  made_here text;
BEGIN
  SELECT 'WHERE key NOT IN (' || string_agg(quote_literal(key), ', ') || ')' INTO made_here
  FROM meta;
  FOR name IN SELECT tablename FROM pg_tables
              WHERE schemaname = current_schema() AND tablename <> 'tinbase_store' LOOP
    PERFORM pg_extension_config_dump(quote_ident(name)::regclass,
                                     CASE WHEN name = 'meta' THEN coalesce(made_here, '') ELSE '' END);
  END LOOP;
  -- The id sequences (migration 0017) too: a restore that restarted them at 1 would hand out ids
  -- the restored rows already hold.
  FOR name IN SELECT sequencename FROM pg_sequences WHERE schemaname = current_schema() LOOP
    PERFORM pg_extension_config_dump(quote_ident(name)::regclass, '');
  END LOOP;
END $$;
