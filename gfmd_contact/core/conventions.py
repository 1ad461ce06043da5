"""Units, signs and Fourier conventions: stated once, used everywhere.

Every module of `gfmd`, `reference` and `verification` follows this page;
docstrings elsewhere only say "units: SI (see gfmd_contact.core.conventions)" and name the
quantities. It follows `shared/reference-formulas.md` §0 ("Convention A").

Units
-----
SI throughout, per unit length out of plane (plane strain):

* lengths, heights, displacements, gaps ............ m
* moduli, tractions, mean pressure p ............... Pa
* works of separation φn, φt ........................ J/m² (= N/m)
* line load F = p·L ................................. N/m
* Fourier-space stiffness K(q) ...................... Pa/m, compliance G = K⁻¹ in m/Pa

Non-dimensional groups (p/E*, φn* = φn/(δn E), a_rel, δ/h_rms) appear only in
plots and reports, and are labelled there.

Geometry and signs
------------------
* The elastic body occupies z ≤ 0 (half-plane) or −D ≤ z ≤ 0 (layer of
  thickness D bonded to a rigid base); its free surface is z = 0 with outward
  normal +z. The rigid indenter is above.
* Grid: N nodes x_j = (j − N/2)·l, l = L/N, periodic with period L, so x = 0
  (node N/2) is the cell centre.
* Displacements u = (u_x, u_z) of the body surface; u_z > 0 is *upward*
  (out of the body, towards the indenter).
* Profile h(x): heights of the indenter's lower surface (zero mean for random
  profiles); the indenter touches first where h is smallest.
* A measured height file (surface.kind = "file", any format) holds z(x), the
  measured surface with z pointing out of the measured material. It enters as
  the indenter's lower surface turned over, h = −z, so that its highest
  measured point touches first (surface.facing = "summits", the default);
  surface.facing = "valleys" takes h = z, the heights as they are
  (`gfmd_contact.core.topography_prep`).
* Indenter position: with U the imposed displacement (downward positive) and
  δ0 the initial separation of the closest points,

      z_ind(x) = h(x) − min(h) + δ0 − U,     penetration δ = U − δ0.

* Gaps are "indenter minus body":

      Δn(x) = z_ind(x) − u_z(x),     Δt(x) = 0 − u_x(x) = −u_x(x)

  (the indenter is rigid and does not move sideways).
* Tractions t = (t_x, t_z) are the tractions *applied on the body* at z = 0.
  An interface law T(Δn, Δt) acts on the body as t_z = T_n, t_x = T_t:
  T_n > 0 is tension (it pulls the body up towards the indenter).
* Mean pressure p = −⟨t_z⟩ (positive = compressive, pushes the body down).
* Hard wall: Δn ≥ 0; contact pressure −t_z ≥ 0 only where Δn = 0.

Fourier convention
------------------
f(x) = Σ_n f̂_n e^{+i q_n x}, q_n = 2πn/L, f̂_n = (1/L)∫ f e^{−i q_n x} dx,
i.e. f̂ = fft(f)/N. The code uses real transforms (`scipy.fft.rfft`), q ≥ 0,
and the 1/N factor cancels wherever two fields transformed the same way are
related, as in t̂ = K(q) û (stiffness) and û = G(q) t̂ (compliance).
The sign s = sign(q) = +1 on the rfft half-spectrum. The elastic traction on
the surface is t_el = −irfft(K · rfft(u)); static equilibrium is
t_el + t_interface = 0 at every node.

Reference point of displacement
-------------------------------
* Half-plane: the q = 0 mode is clamped (⟨u_z⟩ = ⟨u_x⟩ = 0): δ is measured from
  the mean plane of the deformed surface.
* Layer on a rigid base: the q = 0 mode has its stiffness (M/D normal, μ/D
  tangential, reference-formulas §1.5) and δ is measured from the undeformed top.
"""
