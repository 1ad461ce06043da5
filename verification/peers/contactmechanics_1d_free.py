"""ContactMechanics 1.8.3: FreeFFTElasticHalfSpace in 1D fails with a TypeError instead of saying it is 2D only.

`FreeFFTElasticHalfSpace((N,), E, (L,))` raises "TypeError: 'NoneType' object is not subscriptable" from
`_compute_surface_stiffness` (the 1D Green's function is never built). A free half-plane has no displacement
reference far away, so refusing 1D is reasonable; the message could say so.

    python verification/peers/contactmechanics_1d_free.py
"""

from ContactMechanics import FreeFFTElasticHalfSpace

try:
    FreeFFTElasticHalfSpace((64,), 1.0, (1.0,))
    print("1D free half-space: constructed")
except TypeError as exc:
    print(f"1D free half-space: TypeError: {exc}")
print("2D free half-space:", FreeFFTElasticHalfSpace((64, 64), 1.0, (1.0, 1.0)).nb_domain_grid_pts)
