"""The case: reading it (TOML, dicts), checking every value with one line a
problem, and the tables both geometries share."""
