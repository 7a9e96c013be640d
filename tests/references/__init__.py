"""Independent references the tests compare vstpetsc with, written from
the physics and importing nothing of vstpetsc's numerics: an explicit
lumped-mass column on a Coulomb base (coulomb_column), MKZ with extended
Masing rules and an explicit shear column (mkz_reference), the rigid and
coupled sliding block (sliding_block), and Smith's lumped-mass pile
driving (smith). bench/ times vstpetsc against some of them."""
