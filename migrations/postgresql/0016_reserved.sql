-- 0016: a placeholder on this branch only, where migration 0016 (the edit before-images of the
-- history work) is not merged yet; migration numbers may have no gaps. Delete it when that
-- migration is merged. (A statement, as PostgreSQL answers a script of comments alone with an
-- empty-query result.)
SELECT 1;
