"""The laws' exact slab integrals, one pair or node at a time in plain floats:
a penalty contact pair, a Coulomb spring, Smith soil; the default
stiffnesses.  Both geometries call them."""
