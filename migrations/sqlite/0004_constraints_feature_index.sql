-- 0004: constraints by feature. Removing or updating a polygon deletes its constraints (and the
-- update engine reads them); without this index each of those scanned the whole table.
CREATE INDEX constraints_feature ON constraints(feature);
