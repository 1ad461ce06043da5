"""Observables and study helpers shared by the `verification/test_analytic_*.py` cases.

Scenes: `verification.scenes.sinusoid` / `cylinder` (SI, `gfmd_contact.core.conventions`). Every function
here runs GFMD on one scene or reduces its saved fields to what the analytic references
(`reference.analytic`) predict; no tolerance lives here.

* mean pressure p̄ = −⟨t_n⟩ and mean gap ḡ = ⟨Δn⟩: on a half-plane the mean displacement is
  clamped, so p̄(ḡ) (not p̄(δ)) is the clean load–displacement relation;
* hard-wall half-width: (nodes with compressive traction)·l/2, quantised to the grid (error ≲ l);
* cohesive half-width: (nodes with Δn ≤ threshold)·l/2;
* Hertz half-width from the pressure's second moment, a = 2√(∫x²p/∫p): exact for the elliptic
  pressure, free of the node-count quantisation.
"""

from __future__ import annotations

import time

import numpy as np

from verification.metrics import fitted_order
from verification.plots import convergence_plot
from verification.runs import run_gfmd
from verification.scenes import ANALYTIC_TOLERANCE


def run(scene, tolerance=ANALYTIC_TOLERANCE):
    """(Result, wall seconds) of one realization (FIRE at `tolerance`); raises if a step did not converge."""
    from gfmd.solver import Settings
    return run_gfmd(scene, settings=Settings(tolerance=tolerance))


def step_fields(result, k):
    """(x, p(x) compressive-positive, gap, p̄, ḡ) at saved step k."""
    f = result.fields[k]
    p = -np.asarray(f["t_n"], float)
    gap = np.asarray(f["gap"], float)
    return result.x, p, gap, float(np.mean(p)), float(np.mean(gap))


def half_width_compressive(p, spacing):
    """Hard-wall half-width (m): (number of nodes with p > 0)·l/2."""
    return 0.5 * spacing * int(np.count_nonzero(p > 0))


def half_width_gap(gap, threshold, spacing):
    """Cohesive half-width (m): (number of nodes with Δn ≤ threshold)·l/2."""
    return 0.5 * spacing * int(np.count_nonzero(gap <= threshold))


def half_width_second_moment(x, p):
    """a = 2√(Σx²p / Σp) (m): exact for p ∝ √(a² − x²)."""
    return 2.0 * float(np.sqrt(np.sum(x**2 * p) / np.sum(p)))


def convergence_study(measure, levels, metrics):
    """Run `measure(level)` at every refinement level.

    `measure` returns (errors {metric: float}, ...); gives (data, errors {metric: array over levels}, wall s).
    """
    t0 = time.perf_counter()
    data = [measure(level) for level in levels]
    wall = time.perf_counter() - t0
    return data, {m: np.array([d[0][m] for d in data]) for m in metrics}, wall


def orders_in(levels, errors, sign=1):
    """{metric: sign × least-squares slope of log error vs log level} (sign −1 for levels = N)."""
    return {m: sign * fitted_order(levels, e) for m, e in errors.items()}


def print_orders(tag, axis, levels, errors, orders):
    """One line per metric: refinement levels, errors and the fitted order (shown with `pytest -s`)."""
    for m, e in errors.items():
        print(f"{tag} {m}: {axis} {[f'{v:.3g}' for v in levels]} error {[f'{x:.2e}' for x in e]} order {orders[m]:.2f}")


def record_n_study(record, *, case, methods, nodes, length, errors, orders, labels, bounds, min_order,
                   tolerance_source, wall, plots, notes, resolution=None):
    """Record and assert an N-refinement study: per metric the finest-N error against its bound, with a
    convergence plot (error vs l = length/N) after `plots` (the metric-independent ones, e.g. a profile)."""
    h = list(length / np.asarray(nodes, float))
    records = []
    for m in labels:
        conv = convergence_plot(h, list(errors[m]), order=orders[m], xlabel="node spacing l (m)", ylabel=labels[m],
                                title=f"{m}: error vs l (observed order {orders[m]:.2f})")
        rec = record(case=case, metric=f"{labels[m]} at N = {nodes[-1]}", value=float(errors[m][-1]),
                     tolerance=bounds[m], methods=methods, tolerance_source=tolerance_source,
                     resolution={"N": int(nodes[-1]), "N_study": [int(n) for n in nodes], "order": orders[m],
                                 "min_order": min_order[m], **(resolution or {})},
                     wall_s=wall, plots=[plots[0], conv, *plots[1:]],
                     notes=f"{notes}; observed order {orders[m]:.2f} (asserted ≥ {min_order[m]})")
        records.append((m, rec))
    assert_study(records, orders, min_order, errors)


def assert_study(records, orders, min_order, errors):
    """Every observed order ≥ its asserted minimum, and every recorded error within its bound."""
    for m, rec in records:
        assert orders[m] >= min_order[m], (m, orders[m], errors[m])
        assert rec.passed, (m, errors[m])


# ----------------------------------------------------------------------------- N-convergence studies
# A study module (verification.studies.hertz, .westergaard) gives NAME, METRICS, NODES {"ci", "full"},
# SCENE (how its scene is built, in words), DESCRIPTION and measure(N) -> (errors, rows, fields, wall).

def n_study(study_module, nodes):
    """{"nodes", "data" (measure's output per N), "errors" {metric: array over N}, "orders", "wall_s"}."""
    data, errors, wall = convergence_study(study_module.measure, nodes, study_module.METRICS)
    orders = orders_in(nodes, errors, sign=-1)
    return {"nodes": list(nodes), "data": data, "errors": errors, "orders": orders, "wall_s": wall}


def n_study_entry(study_module, st, subset):
    """The data-file entry of an N-convergence study run."""
    from verification import measured

    return measured.make_entry({"N": st["nodes"], "errors": {m: list(e) for m, e in st["errors"].items()},
                                "orders": st["orders"]}, scene=study_module.SCENE, subset=subset,
                               wall_s=st["wall_s"])


def stored_errors(name, subset="ci"):
    """{metric: [error per N]} and the N list of the stored study verification/data/<name>.json."""
    from verification import measured

    values = measured.entry(name, subset)["values"]
    return values["errors"], values["N"]


def n_study_main(study_module, argv=None):
    """Command line of an N-convergence study: print the errors and orders; --write stores them."""
    import argparse

    from verification import measured

    nodes = study_module.NODES
    ap = argparse.ArgumentParser(description=study_module.__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help=f"N up to {nodes['full'][-1]} (entry 'full'); default "
                                                        f"N up to {nodes['ci'][-1]} ('ci')")
    ap.add_argument("--write", action="store_true",
                    help=f"store the errors in verification/data/{study_module.NAME}.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    st = n_study(study_module, np.array(nodes[subset]))
    print_orders(subset, "N", st["nodes"], st["errors"], st["orders"])
    print(f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(study_module.NAME, {subset: n_study_entry(study_module, st, subset)},
                             description=study_module.DESCRIPTION))
