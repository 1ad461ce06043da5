"""Tamaas 2.9: PolonskyKeerRey with the pressure primal accepts an adhesion functional and returns a
"converged" state that is not an equilibrium.

The same sinusoid and ExponentialAdhesionFunctional (V = −w e^{−g/ρ} on the hard wall) are solved twice at the
same mean pressure: with the gap primal (mean-gap control, then its p̄ reused) and with the default pressure
primal. Off contact an equilibrium has p = −(w/ρ) e^{−g/ρ} node by node. The gap-primal state meets it (1.8e-12
w/ρ); the pressure-primal one reports an error below its tolerance (9.5e-13) at the right p̄, but misses the law
by 3.6 w/ρ with ⟨g⟩ = 0.0126 instead of 0.005 (in SI units on a 1 µm cell its gaps reached ~1e7 m). Refusing the
combination, or documenting that adhesion needs the gap primal, would help.

    python verification/peers/tamaas_adhesion_pressure_primal.py
"""

import numpy as np
import tamaas as tm

tm.set_log_level(tm.LogLevel.error)
N, L, E_STAR, H0, W, RHO = 256, 1.0, 1.0, 0.01, 1e-5, 1e-3
x = np.arange(N) * L / N
surface = np.ascontiguousarray(H0 * np.cos(2 * np.pi * x / L))  # summits up


def solve(primal, target):
    model = tm.ModelFactory.createModel(tm.model_type.basic_1d, [L], [N])
    model.E, model.nu = E_STAR, 0.0
    solver = tm.PolonskyKeerRey(model, surface, 1e-12, primal, primal)
    adhesion = tm.ExponentialAdhesionFunctional(surface)
    adhesion.parameters = {"rho": RHO, "surface_energy": W}
    solver.addFunctionalTerm(adhesion)
    error = solver.solve(target)
    p, g = np.array(model.traction).ravel(), np.array(model["gap"]).ravel()
    off = g > 0
    residual = np.max(np.abs(p[off] + W / RHO * np.exp(-g[off] / RHO))) / (W / RHO)
    return error, p.mean(), g, residual


error, pbar, g, residual = solve(tm.PolonskyKeerRey.gap, 0.5 * H0)
print(f"gap primal, ⟨g⟩ = {0.5 * H0:g}: error {error:.1e}, p̄ = {pbar:.6e}, ⟨g⟩ = {g.mean():.4g}, "
      f"max |p − p_law| off contact = {residual:.1e} w/ρ")
error, pbar2, g2, residual2 = solve(tm.PolonskyKeerRey.pressure, pbar)
print(f"pressure primal, p̄ = {pbar:.6e}: error {error:.1e}, p̄ = {pbar2:.6e}, ⟨g⟩ = {g2.mean():.4g}, "
      f"max |p − p_law| off contact = {residual2:.1e} w/ρ")
