-- The SQL functions of the PostgreSQL extension `tinbase` (extensions/postgresql/CMakeLists.txt
-- appends this file to schema/postgresql.sql). They read the store's tables in the caller's
-- transaction, so they see its own uncommitted edits and a ROLLBACK undoes whatever it did.
-- Each pins search_path to the store's schema and PostGIS's (SET search_path FROM CURRENT: the
-- path CREATE EXTENSION ran the script with), so they answer the same from any search_path.
--
-- tinbase_locate, tinbase_z, tinbase_neighbours, tinbase_check, tinbase_add_polygon and
-- tinbase_remove_feature are C++ in the module tinbase.so (extensions/postgresql/*.cc): the
-- engine itself, run through an SPI connection in the caller's transaction. tinbase_profile is
-- still plpgsql: its orientation tests are in double precision, not CGAL's exact predicates.

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

-- Twice the signed area of (a, b, p): positive when p lies left of a->b.
CREATE FUNCTION tinbase_orient(ax double precision, ay double precision, bx double precision,
                               by_ double precision, px double precision, py double precision)
RETURNS double precision LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE AS $$
  SELECT (bx - ax) * (py - ay) - (by_ - ay) * (px - ax)
$$;

-- The surface row of `surface_name`; an error naming it when there is none.
CREATE FUNCTION tinbase_surface(surface_name text) RETURNS surfaces
LANGUAGE plpgsql STABLE STRICT SET search_path FROM CURRENT AS $$
DECLARE
  found_surface surfaces;
BEGIN
  SELECT * INTO found_surface FROM surfaces WHERE name = surface_name;
  IF NOT FOUND THEN
    RAISE EXCEPTION 'tinbase: no surface named %', quote_literal(surface_name)
      USING ERRCODE = 'invalid_parameter_value';
  END IF;
  RETURN found_surface;
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
-- row per station (`start`, every `edge` crossing, each `bend`, `end`) with its plan distance along
-- the line, x, y and z, and the triangle, visibility and tag of the stretch that begins there
-- (none at the end). The walk crosses triangles by their neighbour links; a line that leaves the
-- surface, or whose first point is outside it, is refused naming the place, as by the CLI. The
-- tests are in double precision: a line through a vertex or along an edge may be followed
-- either way there (the CLI's exact walk reports `vertex` stations; this one does not).
CREATE FUNCTION tinbase_profile(surface_name text, line geometry)
RETURNS TABLE(distance double precision, x double precision, y double precision,
              z double precision, kind text, triangle bigint, visible boolean, tag text)
LANGUAGE plpgsql STABLE STRICT SET search_path FROM CURRENT AS $$
#variable_conflict use_column
DECLARE
  s surfaces := tinbase_surface(surface_name);
  n integer := ST_NPoints(line);
  here bigint;
  t record;
  k integer;
  px double precision; py double precision; qx double precision; qy double precision;
  length double precision;
  base double precision := 0;
  ea bigint; eb bigint; en bigint;
  fa double precision; fb double precision; fp double precision; fq double precision;
  crossing double precision;
  guard integer;
BEGIN
  IF GeometryType(line) <> 'LINESTRING' OR n < 2 THEN
    RAISE EXCEPTION 'tinbase_profile: the line must be a LineString of at least two points'
      USING ERRCODE = 'invalid_parameter_value';
  END IF;
  px := ST_X(ST_PointN(line, 1));
  py := ST_Y(ST_PointN(line, 1));
  here := tinbase_locate(surface_name, px, py);
  IF here IS NULL THEN
    RAISE EXCEPTION 'tinbase_profile: point 1 (%, %) is outside surface %', px, py,
      quote_literal(surface_name) USING ERRCODE = 'invalid_parameter_value';
  END IF;
  FOR k IN 2 .. n LOOP
    qx := ST_X(ST_PointN(line, k));
    qy := ST_Y(ST_PointN(line, k));
    length := sqrt((qx - px) ^ 2 + (qy - py) ^ 2);
    guard := 0;
    LOOP
      SELECT tr.id, tr.visible = 1 AS shown, g.value AS tag_value,
             ARRAY[tr.v0, tr.v1, tr.v2] AS v, ARRAY[tr.n0, tr.n1, tr.n2] AS nb,
             ARRAY[a.x, b.x, c.x] AS vx, ARRAY[a.y, b.y, c.y] AS vy, ARRAY[a.z, b.z, c.z] AS vz
        INTO t
      FROM triangles tr
        JOIN vertices a ON a.id = tr.v0 JOIN vertices b ON b.id = tr.v1
        JOIN vertices c ON c.id = tr.v2 LEFT JOIN tags g ON g.id = tr.tag
      WHERE tr.id = here;
      IF k = 2 AND guard = 0 THEN  -- the start, in its triangle
        RETURN QUERY SELECT 0::double precision, px, py,
          (tinbase_orient(t.vx[2], t.vy[2], t.vx[3], t.vy[3], px, py) * t.vz[1] +
           tinbase_orient(t.vx[3], t.vy[3], t.vx[1], t.vy[1], px, py) * t.vz[2] +
           tinbase_orient(t.vx[1], t.vy[1], t.vx[2], t.vy[2], px, py) * t.vz[3]) /
          tinbase_orient(t.vx[1], t.vy[1], t.vx[2], t.vy[2], t.vx[3], t.vy[3]),
          'start'::text, t.id, t.shown, t.tag_value;
      END IF;
      guard := guard + 1;
      -- The edge i (from v[i+1] to v[i+2], across from v[i]) the line leaves by: q beyond it,
      -- its start right of the line and its end left of it.
      en := NULL;
      FOR i IN 1 .. 3 LOOP
        ea := i % 3 + 1;
        eb := (i + 1) % 3 + 1;
        fq := tinbase_orient(t.vx[ea], t.vy[ea], t.vx[eb], t.vy[eb], qx, qy);
        fa := tinbase_orient(px, py, qx, qy, t.vx[ea], t.vy[ea]);
        fb := tinbase_orient(px, py, qx, qy, t.vx[eb], t.vy[eb]);
        IF fq < 0 AND fa <= 0 AND fb >= 0 THEN
          en := i;
          EXIT;
        END IF;
      END LOOP;
      EXIT WHEN en IS NULL;  -- q is in this triangle
      fp := tinbase_orient(t.vx[ea], t.vy[ea], t.vx[eb], t.vy[eb], px, py);
      crossing := fp / (fp - fq);
      IF t.nb[en] IS NULL OR guard > 1000000 THEN
        RAISE EXCEPTION 'tinbase_profile: the line leaves the surface at (%, %) on its way to point %',
          px + crossing * (qx - px), py + crossing * (qy - py), k
          USING ERRCODE = 'invalid_parameter_value';
      END IF;
      here := t.nb[en];
      SELECT tr.visible = 1, g.value INTO t.shown, t.tag_value
      FROM triangles tr LEFT JOIN tags g ON g.id = tr.tag WHERE tr.id = here;
      RETURN QUERY SELECT base + crossing * length, px + crossing * (qx - px),
        py + crossing * (qy - py),
        t.vz[ea] + fa / (fa - fb) * (t.vz[eb] - t.vz[ea]), 'edge'::text, here, t.shown, t.tag_value;
    END LOOP;
    base := base + length;
    RETURN QUERY SELECT base, qx, qy,
      (tinbase_orient(t.vx[2], t.vy[2], t.vx[3], t.vy[3], qx, qy) * t.vz[1] +
       tinbase_orient(t.vx[3], t.vy[3], t.vx[1], t.vy[1], qx, qy) * t.vz[2] +
       tinbase_orient(t.vx[1], t.vy[1], t.vx[2], t.vy[2], qx, qy) * t.vz[3]) /
      tinbase_orient(t.vx[1], t.vy[1], t.vx[2], t.vy[2], t.vx[3], t.vy[3]),
      CASE WHEN k = n THEN 'end' ELSE 'bend' END,
      CASE WHEN k = n THEN NULL ELSE t.id END,
      CASE WHEN k = n THEN NULL ELSE t.shown END,
      CASE WHEN k = n THEN NULL ELSE t.tag_value END;
    px := qx;
    py := qy;
  END LOOP;
END $$;

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
END $$;
