"""Independent references the tests check vstpetsc against, written from
the physics or the literature; none imports vstpetsc (a few read the
typed view of a vstpetsc Case they are given).  The benchmarks in bench/
and the accuracy studies in studies/ import them from here.

- mkz.py: the MKZ backbone with the extended Masing rules, one point and
  an explicit shear column (issue 28);
- sliding_block.py: Newmark's rigid sliding block, exact for a piecewise
  linear record, and the single-mode coupled column (issue 27);
- coulomb_column.py: an explicit lumped-mass shear column on a Coulomb
  base (issue 27);
- yielding_interface.py: the two combined, MKZ soil with a Coulomb base,
  and a block sliding on a yielding column over a Lysmer base;
- smith.py: Smith's (1960) explicit lumped-mass pile-driving algorithm;
- waves.py: the standing wave, the bar's impact on a wall and a soil
  layer's site response, with their exact solutions (issue 26).
- lamb.py: Lamb's problem in plane strain, the surface motion of a
  half-space under a vertical line load, closed form (Cagniard-de Hoop)
  and by wavenumber-frequency integration, with the Rayleigh speed.
- chopra_reservoir.py: the harmonic hydrodynamic pressure on a rigid
  vertical dam face, Chopra's (1967) infinite reservoir, the same truncated
  at a plane-wave dashpot, Fenves & Chopra's absorbing bottom, and the
  incompressible closed form (0.743 rho a H at the heel).
"""
