"""GFMD pull-off of a cylinder on the Lennard-Jones 9-3 wall vs Maugis–Dugdale at λ = 1: errors vs N.

The cross-code pull-off case for codes that have the LJ 9-3 wall but not seed Eq. 3 (`verification.cross_code.
cases`): the cylinder, cell, half-plane and displacement path of `verification.studies.md_pulloff`, the
interface "lj93" with w = 1 J/m² and its equilibrium gap z0 set so that the Dugdale map (w, σ0 = the LJ wall's
peak traction (27/10)(w/z0)x_p⁴, x_p⁶ = 2/5) has λ = 1. Solved through our GFMD's solver adapter
(`verification.solvers.gfmd`), the same route the case runs. As for Eq. 3, the LJ law's shape differs from
Dugdale's, so the error converges in N to a law-shape limit, not to 0; the case holds every code to that limit.

    python -m verification.studies.md_pulloff_lj93 [--write]

prints F/F_MD − 1 at N = 64 … 512 (≈ 10 s); `--write` stores them in verification/data/md_pulloff_lj93.json.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import surfaces
from gfmd_contact.core.law_lj93 import X_PEAK
from reference.analytic import maugis_dugdale as MD
from verification import measured
from verification.solvers.protocol import Interface, Problem
from verification.studies import md_pulloff as mp

NAME = "md_pulloff_lj93"
LAMBDA = 1.0
NODES = (64, 128, 256, 512)
CI_NODES = 128


def sigma0(z0, work=mp.WORK):
    """The LJ 9-3 wall's peak traction (Pa): the Dugdale stress of the map."""
    return 2.7 * work / z0 * X_PEAK**4


def range_length(lam=LAMBDA):
    """z0 (m) whose Dugdale map has Maugis parameter lam (λ ∝ σ0 ∝ 1/z0)."""
    return 1e-9 * MD.maugis_parameter(sigma0(1e-9), mp.RADIUS, mp.e_star(), mp.WORK) / lam


def problem(nodes):
    """The LJ 9-3 cylinder at N = nodes along md_pulloff's displacement path."""
    from gfmd_contact.core.loading import piecewise_path
    return Problem(heights=surfaces.cylinder(nodes, mp.LENGTH, mp.RADIUS), lengths=(mp.LENGTH,),
                   contact_modulus=mp.e_star(), interface=Interface("lj93", mp.WORK, range_length()),
                   boundary="periodic", control="penetration", path=tuple(piecewise_path(mp.PATH, mp.STEPS)),
                   name="md pull-off, LJ 9-3")


def pull_off_md():
    """The Maugis–Dugdale pull-off F_MD (N/m) of the map."""
    return MD.pull_off_load(mp.RADIUS, mp.e_star(), mp.WORK, sigma0(range_length()))


def error(answer):
    """(F − F_MD)/|F_MD|, F = the most tensile p̄·L on the path (signed)."""
    f = min(s.mean_pressure for s in answer.states) * mp.LENGTH
    return (f - pull_off_md()) / abs(pull_off_md())


def study(nodes=NODES):
    from verification.solvers.gfmd import GFMDSolver
    t0 = time.perf_counter()
    errors = [error(GFMDSolver().solve(problem(n))) for n in nodes]
    return {"N": list(nodes), "ci_nodes": CI_NODES, "errors": errors,
            "differences": [float(d) for d in np.abs(np.diff(errors))], "range_length_m": range_length(),
            "F_md_N_per_m": pull_off_md(), "wall_s": time.perf_counter() - t0}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/md_pulloff_lj93.json")
    args = ap.parse_args(argv)
    st = study()
    for n, e in zip(st["N"], st["errors"]):
        print(f"N = {n:5d}: F/F_MD − 1 = {e:+.5f}")
    if args.write:
        wall = st.pop("wall_s")
        entry = measured.make_entry(st, scene="verification.studies.md_pulloff_lj93.problem(N): the md_pulloff "
                                    "cylinder on the LJ 9-3 wall, w = 1 J/m², z0 for λ = 1", wall_s=wall)
        print(measured.write(NAME, {"ci": entry}, description=__doc__.splitlines()[0]))


if __name__ == "__main__":
    main()
