"""The time algebra of a space-time slab and the histories that load it: what
makes the method third order in time, once for both geometries."""
