-- 0004 (PostgreSQL): constraints found by their feature (removing a feature).
CREATE INDEX constraints_feature ON constraints(feature);
