"""κ vs N for the hard-wall self-affine default geometry: the fitted κ converges with the grid.

Study, scene and numbers: `verification.studies.kappa_convergence` (gfmd_contact/core/default_scene.toml as a hard
wall, 4 realizations, N = 1024 … 8192); stored in verification/data/kappa_convergence.json (regenerate:
`python -m verification.studies.kappa_convergence --write`, about a minute).

Fixed physical lengths (λs = 10 nm at every N, entry "hard-wall"): the successive differences of the mean
κ must shrink (every ratio |d_i|/|d_{i+1}| ≥ the worst stored ratio / SAFETY) and κ at the finest N must lie
within its extrapolation error (the last difference) of the Richardson limit — for the stored N = 1024 …
8192 and for the levels this run computes (CI: 1024 … 4096; --full: … 8192). With λs following the grid
(entry "hard-wall-lambda-s-following") κ(N) is recorded with its spread over the realizations, not asserted
to converge: finer N changes the surface there (the study's docstring).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from verification import measured
from verification.plots import convergence_plot, table_plot
from verification.studies import kappa_convergence as kc

CASE = "kappa/hard-wall-self-affine-vs-N"
METHODS = ("gfmd-fire (hard wall, PCG)",)
SAFETY = 1.5


def stored(name, variant=kc.KEY):
    return measured.value(kc.NAME, variant, name)


@pytest.mark.parametrize("nodes", [kc.NODES[:3], pytest.param(kc.NODES, marks=pytest.mark.slow)], ids=["ci", "full"])
def test_kappa_converges_with_n(nodes, verification_record):
    values, walls, wall = kc.study(nodes)
    means, d = values["mean"], values["differences"]
    ratios = [abs(a) / abs(b) for a, b in zip(d, d[1:])]
    worst = min(abs(a) / abs(b) for a, b in zip(stored("differences"), stored("differences")[1:]))
    need = worst / SAFETY
    limit, limit_err = stored("limit"), stored("limit_error")
    finest = means[-1]
    own_err = abs(d[-1])  # this run's extrapolation error at its finest N: the last difference
    rows = [[n, m, s] + list(k) for n, m, s, k in zip(values["N"], means, values["spread"], values["kappa"])]
    res = {"N": list(nodes), "realizations": len(kc.REALIZATIONS), "steps": kc.STEPS, "λs (m)": kc.scene(nodes[0]).surface.rollon_wavelength}
    verification_record(
        case=CASE, metric=f"smallest ratio of successive κ differences |d_i|/|d_i+1|, N = {nodes[0]} … {nodes[-1]}",
        value=min(ratios), tolerance=need, lower_bound=True, methods=METHODS, resolution=res,
        measured=worst, wall_s=wall,
        tolerance_source=(f"≥ the worst stored ratio {worst:.3g} / {SAFETY:g} = {need:.3g} (order ≥ {math.log2(need):.2f}); "
                          f"stored orders {', '.join(f'{o:.2f}' for o in stored('orders'))}"),
        scene=kc.scene(nodes[-1]),
        plots=[convergence_plot([1 / n for n in nodes[1:]], [abs(x) for x in d], xlabel="1/N (of the finer level)",
                                ylabel="|κ(N) − κ(N/2)| (mean over realizations)"),
               table_plot(["N", "mean κ", "spread (max − min)"] + [f"κ realization {r}" for r in kc.REALIZATIONS],
                          rows, title="κ vs N, λs fixed (this run)")])
    verification_record(
        case=CASE, metric=f"|κ(N = {nodes[-1]}) − κ∞| (stored Richardson limit {limit:.4g})", value=abs(finest - limit),
        tolerance=own_err, methods=METHODS, resolution=res, measured=abs(stored("mean")[len(nodes) - 1] - limit),
        tolerance_source=(f"the extrapolation error at N = {nodes[-1]}: |κ(N) − κ(N/2)| of this run; the stored limit "
                          f"is κ(8192) + d/(2^p − 1), error {limit_err:.3g}"))
    assert all(r >= need for r in ratios), (ratios, need)
    assert abs(finest - limit) <= own_err, (finest, limit, own_err)
    assert abs(stored("mean")[-1] - limit) <= limit_err  # the stored finest level within its own estimate


def test_kappa_with_lambda_s_following_the_grid(verification_record):
    """Recorded: κ(N) and its realization spread when λs = 8 L/N (the surface changes with N)."""
    v = measured.entry(kc.NAME, kc.FOLLOWING)["values"]
    rows = [[n, m, s] + list(k) for n, m, s, k in zip(v["N"], v["mean"], v["spread"], v["kappa"])]
    verification_record(case=CASE, metric="κ(N), λs = 8 L/N: mean over realizations at the largest N",
                        value=v["mean"][-1], tolerance=None, passed=None, methods=METHODS,
                        resolution={"N": v["N"], "realizations": len(v["realizations"])},
                        tolerance_source=("informational: finer N adds shorter wavelengths (not a discretisation "
                                          f"convergence); differences {', '.join(f'{x:.3g}' for x in v['differences'])}"),
                        plots=[table_plot(["N", "mean κ", "spread (max − min)"]
                                          + [f"κ realization {r}" for r in v["realizations"]], rows,
                                          title="κ vs N, λs = 8 L/N (stored)")])
    assert np.all(np.isfinite(v["mean"])) and v["N"] == list(kc.NODES)
