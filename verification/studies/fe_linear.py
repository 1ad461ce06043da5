"""FE cell vs the exact bonded-layer compliance under a prescribed sinusoidal surface traction.

A normal traction t_z = cos(q_n x + 0.7) (phase: not symmetric in x) on the periodic bonded
layer L = 1, D = L/2, E = 1: the surface response of the condensed FE cell (`Cell.schur`, the
operator the nonlinear FE solve uses) against the exact layer kernel (`gfmd_contact.core.kernels.layer_normal`
for u_z with t_x = 0, `layer_coupled` for u_x): relative compliance error of mode n, the max of
the u_z error and the u_x error (the latter relative to 1/k_zz). Measured per ν at N = 64:
P2 modes n = 1, 4 (≥ 16 nodes per wavelength), P1 mode n = 1 (volumetric locking as ν → ½),
and the P2 convergence of mode n = 4 at ν = 0.4999 over N = 32, 64, 128.

    python -m verification.studies.fe_linear [--write]

`--write` stores them in verification/data/fe_linear.json (entry "ci"), which test_fe_linear.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import kernels
from reference._blas import single_thread
from reference.fem.assembly import build_cell
from verification import measured

NAME = "fe_linear"
L, D, E = 1.0, 0.5, 1.0
RATIOS = (0.3, 0.49, 0.4999)
CONVERGENCE_NODES = (32, 64, 128)


def compliance_errors(n_nodes, nu, order, modes):
    with single_thread():
        return _compliance_errors(n_nodes, nu, order, modes)


def _compliance_errors(n_nodes, nu, order, modes):
    cell = build_cell(n_nodes, L, D, E, nu, order=order)
    s, _ = cell.schur(("x", "z"))
    ns = cell.surface_x.size
    vp = cell.vertex_points
    out = {}
    for n in modes:
        q = 2 * np.pi * n / L
        t = np.cos(q * cell.surface_x + 0.7)
        u = np.linalg.solve(s, np.concatenate([np.zeros(ns), cell.weights * t]))
        th = np.fft.rfft(t[vp])[n]
        uzh, uxh = np.fft.rfft(u[ns:][vp])[n], np.fft.rfft(u[:ns][vp])[n]
        k_zz = kernels.layer_normal(np.array([q]), E, nu, D)[0]
        kxx, kxz, kzz = kernels.layer_coupled(np.array([q]), E, nu, D)
        g = np.linalg.inv(np.array([[kxx[0], kxz[0]], [-kxz[0], kzz[0]]]))
        err_z = abs(uzh / th * k_zz - 1)
        # u_x: error relative to the normal compliance (G_xz → 0 as ν → ½)
        err_x = abs(uxh / th - g[0, 1]) * k_zz
        out[n] = max(err_z, err_x)
    return out


def study():
    """{"values": {"p2_worst": {ν: max error of P2 modes 1, 4}, "p1_n1": {ν: P1 mode-1 error},
    "convergence_nodes", "convergence_errors" (P2, mode 4, ν = 0.4999)}, "wall_s"}."""
    t0 = time.perf_counter()
    p2_worst, p1_n1 = {}, {}
    for nu in RATIOS:
        p2 = compliance_errors(64, nu, 2, (1, 4))
        p2_worst[str(nu)] = float(max(p2[1], p2[4]))
        p1_n1[str(nu)] = float(compliance_errors(64, nu, 1, (1,))[1])
    errs = [float(compliance_errors(n, 0.4999, 2, (4,))[4]) for n in CONVERGENCE_NODES]
    return {"values": {"p2_worst": p2_worst, "p1_n1": p1_n1, "convergence_nodes": list(CONVERGENCE_NODES),
                       "convergence_errors": errs}, "wall_s": time.perf_counter() - t0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/fe_linear.json")
    args = ap.parse_args(argv)
    st = study()
    print(st["values"], f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {"ci": measured.make_entry(st["values"], scene=f"layer L = {L}, D = {D}, E = {E}, N = 64",
                                                              subset="ci", wall_s=st["wall_s"])},
                             description="FE P1/P2 layer compliance vs the exact kernel (sinusoidal traction)"))


if __name__ == "__main__":
    main()
