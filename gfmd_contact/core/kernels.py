"""Fourier-space surface stiffness of a periodic elastic body, plane strain.

Units: SI (see `gfmd_contact.core.conventions`): q in 1/m, moduli in Pa, thickness in m,
stiffness K(q) in Pa/m, so that t̂ = K(q) û with û, t̂ transformed alike.
Formulas: reference-formulas §1 (Convention A: u_z up, tractions on the body).

Coupled kernels are returned as the three arrays (K_xx, K_xz, K_zz) on the rfft
half-spectrum q ≥ 0; K_zx = conj(K_xz) = −K_xz (Hermitian, K_xz imaginary).
The Nyquist mode's off-diagonal entry is set to zero (§1.6) so real fields stay
real. Half-plane entries at q = 0 are zero (the mean is clamped by the solver);
layer entries at q = 0 are the uniform-strain values (§1.5).
"""

from __future__ import annotations

import numpy as np

#: qD beyond which a layer is indistinguishable from the half-plane in double
#: precision (relative difference ~ (qD)² e^{−2qD} < 1e-30 at qD = 40)
_HALF_PLANE_QD = 40.0


def wavenumbers(nodes, length):
    """Non-negative wavenumbers q_n = 2πn/L of the rfft half-spectrum (1/m)."""
    return 2.0 * np.pi * np.fft.rfftfreq(nodes, d=length / nodes)


def wavevector_magnitudes(nodes_x, length_x, nodes_y, length_y):
    """|q| = (q_x² + q_y²)^½ (1/m) on the rfft2 half-spectrum of an Nx × Ny grid: shape (Nx, Ny//2 + 1).

    Axis 0 is x (all Nx modes, `np.fft.fftfreq` order), axis 1 is y (the Ny//2 + 1 non-negative
    modes), as `numpy.fft.rfft2` / `scipy.fft.rfftn` over the last two axes lay them out. For a
    frictionless normal load the 2+1-D response to the plane wave e^{i q·x} is the plane-strain
    response along q (the elastic problem is two-dimensional in the plane spanned by q and z),
    so `halfplane_normal` and `layer_normal` evaluated at these |q| are the half-space and bonded
    layer normal stiffnesses of 2+1-D (reference-formulas §1.1, §1.3 with q → |q|).
    """
    qx = 2.0 * np.pi * np.fft.fftfreq(nodes_x, d=length_x / nodes_x)
    qy = 2.0 * np.pi * np.fft.rfftfreq(nodes_y, d=length_y / nodes_y)
    return np.hypot(qx[:, None], qy[None, :])


def contact_modulus(youngs_modulus, poisson_ratio):
    """E* = E/(1 − ν²) (Pa), plane strain, rigid indenter."""
    return youngs_modulus / (1.0 - poisson_ratio**2)


def shear_modulus(youngs_modulus, poisson_ratio):
    """μ = E/(2(1 + ν)) (Pa)."""
    return youngs_modulus / (2.0 * (1.0 + poisson_ratio))


def constrained_modulus(youngs_modulus, poisson_ratio):
    """Oedometric modulus M = E(1 − ν)/((1 + ν)(1 − 2ν)) (Pa); infinite at ν = 1/2."""
    if poisson_ratio >= 0.5:
        return np.inf
    return youngs_modulus * (1 - poisson_ratio) / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio))


def _nyquist_mask(q, nodes):
    mask = np.zeros(q.shape, bool)
    if nodes % 2 == 0:
        mask[-1] = True
    return mask


def halfplane_normal(q, youngs_modulus, poisson_ratio):
    """Frictionless half-plane, normal only: k(q) = E*|q|/2 (Pa/m), §1.1."""
    return 0.5 * contact_modulus(youngs_modulus, poisson_ratio) * np.abs(q)


def halfplane_coupled(q, youngs_modulus, poisson_ratio, nodes=None):
    """Half-plane 2×2 stiffness (K_xx, K_xz, K_zz), §1.2.

    K = (E*|q|/2)/(1 − β²) [[1, iβs], [−iβs, 1]], β = (1 − 2ν)/(2(1 − ν)).
    `nodes` (grid size) identifies the Nyquist mode, whose coupling is zeroed.
    """
    nu = poisson_ratio
    beta = (1 - 2 * nu) / (2 * (1 - nu))
    f = halfplane_normal(q, youngs_modulus, nu) / (1 - beta**2)
    s = np.sign(q)
    k_xz = 1j * beta * s * f
    if nodes is not None:
        k_xz[_nyquist_mask(q, nodes)] = 0.0
    return f.astype(complex), k_xz, f.astype(complex)


def _layer_terms(q, youngs_modulus, poisson_ratio, thickness):
    nu = poisson_ratio
    hq = np.abs(q) * thickness
    k3 = 3 - 4 * nu
    f = halfplane_normal(q, youngs_modulus, nu)
    return nu, hq, k3, f


def layer_normal(q, youngs_modulus, poisson_ratio, thickness):
    """Layer of thickness D on a bonded rigid base, frictionless top: k = 1/G_zz (Pa/m).

    k(q) = (E*|q|/2) [k3 cosh 2H + 2H² + 5 − 12ν + 8ν²]/[k3 sinh 2H − 2H], H = |q|D,
    k3 = 3 − 4ν (§1.3); k(0) = M/D (§1.5). Requires ν < 1/2.
    """
    nu, hq, k3, f = _layer_terms(q, youngs_modulus, poisson_ratio, thickness)
    k = np.empty_like(f)
    zero = hq == 0
    deep = hq > _HALF_PLANE_QD
    mid = ~(zero | deep)
    h = hq[mid]
    num = k3 * np.cosh(2 * h) + 2 * h**2 + 5 - 12 * nu + 8 * nu**2
    den = k3 * np.sinh(2 * h) - 2 * h
    k[mid] = f[mid] * num / den
    # deep limit: num/den → 1 (up to (qD)² e^{−2qD})
    k[deep] = f[deep]
    k[zero] = constrained_modulus(youngs_modulus, nu) / thickness
    return k


def layer_coupled(q, youngs_modulus, poisson_ratio, thickness, nodes=None):
    """Layer on a bonded rigid base, 2×2 stiffness (K_xx, K_xz, K_zz), §1.3/§1.5.

    With H = |q|D, S = k3² sinh²H − H², f = E*|q|/2:
    K_xx = f 2(1−ν)² [k3 sinh 2H − 2H]/S,  K_zz = f 2(1−ν)² [k3 sinh 2H + 2H]/S,
    K_xz = i s f 2(1−ν) [(1−2ν) k3 sinh²H − H²]/S;  K(0) = diag(μ/D, M/D).
    """
    nu, hq, k3, f = _layer_terms(q, youngs_modulus, poisson_ratio, thickness)
    k_xx_hp, k_xz_hp, k_zz_hp = halfplane_coupled(q, youngs_modulus, nu)
    k_xx = k_xx_hp.copy()
    k_xz = k_xz_hp.copy()
    k_zz = k_zz_hp.copy()
    zero = hq == 0
    mid = ~zero & (hq <= _HALF_PLANE_QD)
    h = hq[mid]
    sh = np.sinh(h)
    s_den = k3**2 * sh**2 - h**2
    k_xx[mid] = f[mid] * 2 * (1 - nu) ** 2 * (k3 * np.sinh(2 * h) - 2 * h) / s_den
    k_zz[mid] = f[mid] * 2 * (1 - nu) ** 2 * (k3 * np.sinh(2 * h) + 2 * h) / s_den
    k_xz[mid] = 1j * np.sign(q[mid]) * f[mid] * 2 * (1 - nu) * ((1 - 2 * nu) * k3 * sh**2 - h**2) / s_den
    k_xx[zero] = shear_modulus(youngs_modulus, nu) / thickness
    k_zz[zero] = constrained_modulus(youngs_modulus, nu) / thickness
    k_xz[zero] = 0.0
    if nodes is not None:
        k_xz[_nyquist_mask(q, nodes)] = 0.0
    return k_xx, k_xz, k_zz
