-- 0007 (PostgreSQL): the vertex kind check as a chain of comparisons (SQLite rebuilt the table
-- for it; PostgreSQL replaces the check alone).
ALTER TABLE vertices DROP CONSTRAINT vertices_kind_check;
ALTER TABLE vertices ADD CONSTRAINT vertices_kind_check CHECK (kind = 'dem' OR kind = 'lidar' OR
  kind = 'ring' OR kind = 'steiner' OR kind = 'user');
