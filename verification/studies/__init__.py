"""Verification studies: the sweeps that measure the numbers the verification tests assert on.

Plain functions (no pytest); each module runs from the command line and, with `--write`,
regenerates its data file under `verification/data/` (`verification.measured`):

* `westergaard`: GFMD hard wall vs Westergaard's sinusoid, error vs N;
* `hertz`: GFMD hard wall vs Hertz line contact, error vs N;
* `jkr_sinusoid`: GFMD cohesive sinusoid vs Johnson's JKR-wavy solution, error vs δn;
* `maugis_dugdale`: GFMD cohesive cylinder vs Maugis–Dugdale at λ = 3 and 1, signed error vs N;
* `fe_cohesive`: GFMD vs FE P2 on the cohesive sinusoid (normal law), differences vs N;
* `fe_coupled`: the same with the coupled law (c = 0.5) at ν = 0.1 … 0.49;
* `fe_jump`: GFMD vs FE P2 through a jump into contact (φn* = 0.15), differences vs N;
* `fe_quadrature`: FE P2 nodal vs Gauss boundary quadrature vs GFMD, differences vs N;
* `fe_selfaffine`: GFMD vs FE P2 on self-affine profiles (H = 0.8, 0.2), differences vs N;
* `reduced_models`: coupled vs normal-only law, forced full vs reduced unknowns, half-plane vs layer;
* `kappa_convergence`: κ vs N for the hard-wall self-affine default geometry, Richardson limit;
* `kappa_2d`: κ vs N × N for hard-wall self-affine surfaces in 2+1-D, against published 2+1-D values;
* `fe_linear`: FE P1/P2 layer compliance vs the exact kernel, per ν, and P2 convergence at ν → ½;
* `speed_accuracy`: error vs wall time of GFMD (FIRE, Verlet) and FE (P1, P2) on three scenes;
* `extremes`: one-parameter sweeps and corners around a base scene, GFMD vs FE on layer cells,
  and the δn/l resolution threshold.
"""
