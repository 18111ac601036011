-- 0009 (PostgreSQL): a triangle's tag is checked by `tinbase check`, not by a foreign key (as
-- migrations/sqlite/0009_triangle_tag_unenforced.sql).
ALTER TABLE triangles DROP CONSTRAINT triangles_tag_fkey;
