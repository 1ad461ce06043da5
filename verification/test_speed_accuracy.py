"""Speed–accuracy trade: error vs wall time of every method and setting (issue #5).

Scenes (SI; `SCENES`): (a) adhesive sinusoid, normal CZ φn* = 0.01 (as verification/test_fe_cohesive);
(b) adhesive self-affine, normal CZ φn* = 0.01, layer D = L; (c) the same profile, frictionless hard wall.
Methods and settings (`plan`): GFMD FIRE and Verlet at N × force tolerance (× p_ref), FE P1 and P2 at N
(Newton / primal–dual active set to 1e-10; default graded mesh). Wall time = the whole run (FE: mesh,
assembly and condensation included), best of two for runs under 1 s, single-threaded BLAS, one run on a
shared 2-core machine: ratios within one table are meaningful, absolute times only roughly.

Reference (`REFERENCE_TEXT`): GFMD FIRE, tolerance 1e-10, N_ref = 1024 (CI subset) or 4096 (full): there is
no analytic solution for these scenes, and the most refined GFMD is the most accurate run available (below).
Errors, all against the reference at the same load steps (`errors`): e_a = max_k |a_rel − a_ref| (absolute;
includes the O(1/N) quantisation of a node count, identical for all methods at equal N), e_p = relative L2
of p(δ) over the steps, e_t = relative L2 of t_n at the last step, the reference sampled on the run's nodes
(every N_ref/N-th node coincides). The self-affine profile is translated so that its lowest point is a node
of every grid (`centred_self_affine_path`): otherwise z_ind (which uses the nodal min of h) shifts with N.

Full sweep (pytest --full, reference N = 4096), e_p at the tightest setting (GFMD tolerance 1e-8), wall s:

    (a) N          64       128      256      512      1024
    GFMD FIRE      4.9e-6   4.1e-9   2.4e-9   2.4e-9   2.4e-9     0.25 … 0.45 s
    GFMD Verlet    4.9e-6   1.8e-8   1.9e-8   1.9e-8   1.9e-8     0.40 … 1.8 s
    FE P1          3.8e-3   3.2e-3   2.8e-3   2.7e-3              0.05 … 0.63 s
    FE P2          8.0e-4   1.4e-4   1.9e-5   7.9e-7              0.22, 0.36, 1.2, 6.4 s
    (b)
    GFMD FIRE      3.1e-3   3.7e-5   1.8e-8   1.4e-8   1.4e-8     0.13 … 0.20 s
    GFMD Verlet    3.1e-3   3.7e-5   1.2e-7   1.3e-7   1.3e-7     0.23 … 2.1 s
    FE P1          2.8e-2   1.3e-2   9.2e-3   7.3e-3              0.06 … 0.61 s
    FE P2          1.4e-2   2.2e-3   3.3e-4   3.2e-5              0.33, 0.59, 1.5, 6.5 s
    (c) (FIRE and Verlet agree to 2 digits)
    GFMD           9.4e-3   2.9e-3   9.8e-4   9.3e-5   4.1e-5     0.06 … 0.57 s
    FE P1          3.0e-2   1.3e-2   8.6e-3   6.4e-3              0.07 … 0.34 s
    FE P2          6.0e-3   1.5e-3   3.6e-4   6.4e-5              0.43, 0.64, 1.5, 3.9 s
    e_t (c)        GFMD 0.17, 0.072, 0.035, 0.019, 0.0089; FE P2 0.21, 0.076, 0.036, 0.028; P1 0.17 … 0.085

* GFMD converges spectrally on the adhesive scenes (smooth band-limited fields) until its solver tolerance
  (1e-8 × p_ref leaves 2e-9 … 1.3e-7 in p); with order ≈ 1.7 on the hard wall (√-singular contact edges).
* FE P2 converges with order ≈ 2.5–3.3; FE P1 stalls at 3e-3 … 6e-3: the graded mesh keeps ≥ 32 bulk
  segments of L/32 that refining N does not touch (tests/test_fem_hardwall.py: the same floor on
  Westergaard), and its nodal pressures oscillate on the alternating-diagonal top row.
* Tolerance: 1e-2 leaves 4e-3 … 1e-1 error in p (Verlet worse than FIRE), 1e-4 leaves 3e-5 … 1.5e-3.
* e_a is the same for every method at equal N (1/N quantisation): to get a_rel to 1 % one needs N ≥ 128
  (sinusoid) or 256 (self-affine) whatever the method.

Time to reach 1 % (e_a < 0.01 absolute; e_p < 0.01) and 0.1 % in p, cheapest setting, wall s (CI run):

    scene  target        GFMD needs                          FE needs
    (a)    a_rel 1 %     0.03 s (Verlet N=256, tol 1e-2)     0.15 s (P1 N=128)
    (a)    p 1 %         0.02 s (Verlet N=64, tol 1e-2)      0.10 s (P1 N=64)
    (a)    p 0.1 %       0.11 s (Verlet N=64, tol 1e-4)      0.49 s (P2 N=64)
    (b)    a_rel 1 %     0.03 s (FIRE N=256, tol 1e-2)       0.29 s (P1 N=256)
    (b)    p 1 %         0.02 s (FIRE N=64, tol 1e-2)        0.29 s (P1 N=256)
    (b)    p 0.1 %       0.07 s (FIRE N=128, tol 1e-4)       2.05 s (P2 N=256)
    (c)    a_rel 1 %     0.02 s (Verlet N=256, tol 1e-2)     0.19 s (P1 N=256)
    (c)    p 1 %         0.02 s (FIRE N=128, tol 1e-2)       0.19 s (P1 N=256)
    (c)    p 0.1 %       0.07 s (FIRE N=256, tol 1e-4)       1.35 s (P2 N=256)

The full run picked the same settings (0.1 % on (c): GFMD FIRE N=1024, tol 1e-2, 0.06 s; FE P2 N=256,
1.15 s): GFMD is 5–15× cheaper than FE at 1 % and 4–30× at 0.1 %. The wall times of the cheapest GFMD runs
(10–30 ms for 13–21 load steps) are near the timer's useful resolution on this machine: read them as
"< 0.1 s".

Assertions (able to fail; derived from the study above):
1. per method (GFMD FIRE and Verlet at tolerance 1e-8, FE P1, FE P2) e_p decreases strictly with each
   doubling of N, pairs whose finer error is below `NOISE_FLOOR` = 1e-6 (GFMD's tolerance plateau, 1.3e-7
   measured at worst) skipped, and e_p(finest) < e_p(coarsest). Worst measured ratio: 0.94 (P1 (a)).
2. the most refined GFMD FIRE (tolerance 1e-8) and FE P2, on FE's finest grid, agree in p(δ) within 3× the
   measured difference and in a_rel within 4/N (measured 0 … 2/N):

       p rel. L2   (a)        (b)        (c)
       CI, N=256   1.9e-5     3.3e-4     1.3e-3
       full, N=512 7.9e-7     3.2e-5     1.3e-4

CI subset: N = 64, 128, 256, GFMD tolerances 1e-2, 1e-4, 1e-8, reference N = 1024: 34–36 s for the
three scenes (measured under load 3–4); the full sweep (N to 1024/512, tolerance 1e-6 too, reference 4096)
is @pytest.mark.slow, 102 s. Each record's notes say which subset ran.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import pytest

from gfmd.loading import run_realization as gfmd_run
from contact.observables import contact_mask
from contact.scene import Scene
from gfmd.solver import Settings
from reference import fem
from verification import harness

# ----------------------------------------------------------------------------- scenes
_MATERIAL = {"material.youngs_modulus": 70e9, "material.poisson_ratio": 0.3}
_SELF_AFFINE = {"surface.kind": "self-affine", "surface.realizations": 1, "surface.length": 1e-6,
                "surface.hurst": 0.8, "surface.h_rms": 5e-9, "surface.rolloff_wavelength": 250e-9,
                "surface.rollon_wavelength": 1e-6 / 16, "surface.seed": 3, "surface.nodes": 1024}
_PROFILE_DIR = []


def centred_self_affine_path(n):
    """Path of a .npy file with the self-affine profile of `_SELF_AFFINE` (m) at N = n nodes, translated so
    that its lowest point is the node x = 0 of every grid.

    Why: z_ind = h − min_nodes h + δ0 − U uses the minimum over the *nodes*; for a profile whose lowest point
    falls between nodes, min_nodes h, hence the indenter position at equal U, changes with N. Measured before
    this: GFMD p(δ) agreed to 1e-11 between N = 512 and 1024 and to 1e-14 between 2048 and 8192, but the two
    groups differed by 1.9e-4 (rel. L2): a rigid indenter shift, not discretisation. The profile has 16
    modes (λs = L/16), so its Fourier series is exact on every N ≥ 64 and is evaluated directly.
    """
    import atexit
    import shutil
    import tempfile
    from pathlib import Path
    from contact import surfaces
    if not _PROFILE_DIR:  # one folder per process, removed at exit (the profile is rebuilt from _SELF_AFFINE)
        _PROFILE_DIR.append(Path(tempfile.mkdtemp(prefix="speed_accuracy_profiles_")))
        atexit.register(shutil.rmtree, _PROFILE_DIR[0], ignore_errors=True)
    path = _PROFILE_DIR[0] / f"self_affine_{n}.npy"
    if not path.exists():
        base = Scene().replace(**_SELF_AFFINE).surface
        h = surfaces.profile(base)
        length = base.length
        coef = np.fft.rfft(h) / h.size
        k = np.flatnonzero(np.abs(coef) > 1e-12 * np.abs(coef).max())
        amp, q = np.where(k == 0, 1.0, 2.0) * coef[k], 2 * np.pi * k / length

        def series(x, derivative=0):  # h(x) and its x-derivatives; samples start at x = −L/2
            phase = np.exp(1j * np.outer(np.atleast_1d(x) + length / 2, q))
            return ((1j * q) ** derivative * amp * phase).real.sum(axis=1)

        x_grid = surfaces.grid(h.size, length)
        x_min = x_grid[np.argmin(h)]
        for _ in range(20):  # Newton on h'(x) = 0 from the lowest node
            step = series(x_min, 1)[0] / series(x_min, 2)[0]
            x_min -= step
            if abs(step) < 1e-15 * length:
                break
        np.save(path, series(surfaces.grid(n, length) + x_min))
    return str(path)


def _self_affine_surface(n):
    return {"surface.kind": "file", "surface.path": centred_self_affine_path(n), "surface.nodes": n,
            "surface.length": _SELF_AFFINE["surface.length"], "surface.realizations": 1,
            "material.thickness": 1e-6}


def adhesive_sinusoid(n):
    """(a) h = −a cos(2πx/L), a = 50 nm, L = 1 µm, layer D = L, normal CZ φn* = 0.01, δn = 1 nm,
    δ from −2 nm to 60 nm in 20 steps (verification/test_fe_cohesive.scene)."""
    return Scene().replace(**_MATERIAL, **{
        "surface.kind": "sinusoid", "surface.realizations": 1, "surface.nodes": n, "surface.length": 1e-6,
        "surface.amplitude": 50e-9, "material.thickness": 1e-6, "interface.law": "cohesive",
        "interface.phi_n_star": 0.01, "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0,
        "loading.initial_separation": 2e-9, "loading.final_penetration": 60e-9, "loading.steps": 20,
        "output.field_steps": 1})


def adhesive_self_affine(n):
    """(b) self-affine H = 0.8, h_rms = 5 nm, L = 1 µm, λr = 250 nm, λs = L/16 (the same 16 modes at every
    N ≥ 64), seed 3, lowest point on the node x = 0 (`centred_self_affine_path`), layer D = L, normal CZ
    φn* = 0.01, δn = 1 nm, δ from −5 nm to 10 nm in 15 steps.

    δ0 = 5 nm > δ_jump = 4.0 δn (contact.model.jump_in_separation): started at δ0 = 2 nm, inside the jump-in
    range, the jump at the first steps picked N-dependent equilibria: GFMD N = 512 and 1024 agreed to 1e-11
    in p(δ), 2048…8192 to 1e-14, but the two groups differed by 1.9e-4 (rel. L2), growing along the ramp."""
    return Scene().replace(**_MATERIAL, **_self_affine_surface(n), **{
        "interface.law": "cohesive", "interface.phi_n_star": 0.01,
        "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0, "loading.initial_separation": 5e-9,
        "loading.final_penetration": 10e-9, "loading.steps": 15, "output.field_steps": 1})


def hard_wall_self_affine(n):
    """(c) the profile of (b), frictionless hard wall, layer D = L, δ from 0 to 12 nm in 12 steps."""
    return Scene().replace(**_MATERIAL, **_self_affine_surface(n), **{
        "interface.law": "hard-wall", "loading.initial_separation": 0.0,
        "loading.final_penetration": 12e-9, "loading.steps": 12, "output.field_steps": 1})


SCENES = {"adhesive-sinusoid": adhesive_sinusoid, "adhesive-self-affine": adhesive_self_affine,
          "hard-wall-self-affine": hard_wall_self_affine}


# ----------------------------------------------------------------------------- settings and runs
@dataclass(frozen=True)
class Setting:
    """One method at one resolution: method in harness.METHODS names or "fe-p1"/"fe-p2"; nodes N;
    tolerance: GFMD force-residual tolerance (× p_ref), None for FE (Newton/PDAS to 1e-10)."""

    method: str
    nodes: int
    tolerance: float | None = None

    @property
    def label(self):
        tol = f", tol {self.tolerance:.0e}" if self.tolerance is not None else ""
        return f"{self.method} N={self.nodes}{tol}"

    @property
    def family(self):
        return "GFMD" if self.method.startswith("gfmd") else "FE"


def run_setting(scene_of, setting, all_fields=False):
    """(Result, wall time in s of the whole run, FE setup included); all_fields: save every step's fields."""
    sc = scene_of(setting.nodes)
    if all_fields:
        sc = sc.replace(**{"output.field_steps": sc.loading.steps})
    t0 = time.perf_counter()
    if setting.family == "GFMD":
        integrator = setting.method.split("-")[1]
        result = gfmd_run(sc, settings=Settings(method=integrator, tolerance=setting.tolerance,
                                                max_iterations=200_000), method_name=setting.method)
    else:
        result = fem.run_realization(sc, order=int(setting.method[-1]))
    wall = time.perf_counter() - t0
    if not result.all_converged:
        raise AssertionError(f"{setting.label}: not converged: {result.messages[:3]}")
    return result, wall


def errors(result, reference):
    """Errors of `result` against `reference` (same load steps, reference on a finer grid whose every
    m-th node is a node of `result`, fields saved at every step):

    a:     max_k |a_rel − a_rel,ref| (absolute; includes the O(1/N) quantisation of a node count);
    a_nodes: max_{k≥1} |a_rel − ⟨contact_ref⟩ on this run's nodes| (the reference's contact set sampled
           on the coarse nodes: the method's own error in deciding contact, without quantisation);
    p:     ‖p − p_ref‖₂/‖p_ref‖₂ over the steps (relative L2 of p(δ));
    t:     ‖t_n − t_n,ref‖₂/‖t_n,ref‖₂ at the last step, the reference sampled on this run's nodes.
    """
    n, n_ref = result.x.size, reference.x.size
    m = n_ref // n
    if n_ref % n or not np.allclose(reference.x[::m], result.x):
        raise ValueError(f"reference grid (N = {n_ref}) does not contain the nodes of N = {n}")
    if not np.allclose(result.curve["delta"], reference.curve["delta"]):
        raise ValueError("reference and run have different load steps")
    steps = np.arange(1, len(reference.curve["delta"]))  # step 0 (U = 0) has no saved fields
    missing = [k for k in steps if k not in reference.fields]
    if missing:
        raise ValueError(f"reference lacks the fields of steps {missing[:5]}: run it with output.field_steps = steps")
    iface = reference.scene.interface
    a_nodes = [np.mean(contact_mask(iface, reference.fields[k]["gap"][::m], reference.fields[k]["t_n"][::m]))
               for k in steps]
    k, k_ref = max(result.fields), max(reference.fields)
    t_ref = reference.fields[k_ref]["t_n"][::m]
    return {"a": float(np.max(np.abs(result.curve["a_rel"] - reference.curve["a_rel"]))),
            "a_nodes": float(np.max(np.abs(result.curve["a_rel"][steps] - np.asarray(a_nodes)))),
            "p": harness.relative_l2(result.curve["p"], reference.curve["p"], reference.curve["p"]),
            "t": harness.relative_l2(result.fields[k]["t_n"], t_ref, t_ref)}


def plan(subset):
    """Settings of the sweep. "ci": N = 64…256, GFMD tolerances 1e-2, 1e-4, 1e-8; "full": N = 64…1024 (GFMD),
    64…512 (FE), tolerances 1e-2, 1e-4, 1e-6, 1e-8. Reference: GFMD FIRE, tolerance 1e-10, N_ref = 1024 (ci)
    or 4096 (full)."""
    if subset == "ci":
        ns_g, ns_f, tols, n_ref = (64, 128, 256), (64, 128, 256), (1e-2, 1e-4, 1e-8), 1024
    else:
        ns_g, ns_f, tols, n_ref = (64, 128, 256, 512, 1024), (64, 128, 256, 512), (1e-2, 1e-4, 1e-6, 1e-8), 4096
    settings = [Setting(m, n, t) for m in ("gfmd-fire", "gfmd-verlet") for n in ns_g for t in tols]
    settings += [Setting(m, n) for m in ("fe-p1", "fe-p2") for n in ns_f]
    return settings, Setting("gfmd-fire", n_ref, 1e-10)


_STUDIES = {}
REPEAT_BELOW_S = 1.0  # s: runs cheaper than this are timed twice, the minimum is kept


def study(name, subset):
    """Run the sweep of `subset` on scene `name`: {"reference", "rows": [(Setting, wall_s, errors, Result)]}."""
    key = (name, subset)
    if key not in _STUDIES:
        scene_of = SCENES[name]
        settings, ref_setting = plan(subset)
        reference, ref_wall = run_setting(scene_of, ref_setting, all_fields=True)
        rows = []
        for s in settings:
            result, wall = run_setting(scene_of, s)
            if wall < REPEAT_BELOW_S:  # cheap runs: best of two (first-call and load noise)
                wall = min(wall, run_setting(scene_of, s)[1])
            rows.append((s, wall, errors(result, reference), result))
        _STUDIES[key] = {"reference": (ref_setting, ref_wall, reference), "rows": rows}
    return _STUDIES[key]


def cheapest_below(rows, family, metric, level=0.01):
    """(wall s, label) of the cheapest setting of `family` with error[metric] < level, or None."""
    ok = [(wall, s.label) for s, wall, e, _ in rows if s.family == family and e[metric] < level]
    return min(ok) if ok else None


def time_to_accuracy_rows(name, rows, level=0.01):
    """Table rows "to reach 1 % error in a_rel / p (and 0.1 % in p): GFMD needs X s, FE needs Y s"."""
    out = []
    for metric, what, lvl in (("a", "|a_rel − a_ref| (absolute)", level), ("p", "p(δ) rel. L2", level),
                              ("p", "p(δ) rel. L2", level / 10)):
        cells = []
        for family in ("GFMD", "FE"):
            best = cheapest_below(rows, family, metric, lvl)
            cells.append("not reached" if best is None else f"{best[0]:.2f} s ({best[1]})")
        out.append([name, f"to reach {lvl:.1%} error in {what}", *cells])
    return out


def print_study(name, st):
    ref_s, ref_wall, _ = st["reference"]
    print(f"\n== {name}: reference {ref_s.label} ({ref_wall:.2f} s)")
    print(f"{'setting':34s} {'wall s':>8s} {'e_a':>9s} {'e_a,nodes':>9s} {'e_p':>9s} {'e_t':>9s}")
    for s, wall, e, _ in st["rows"]:
        print(f"{s.label:34s} {wall:8.2f} {e['a']:9.2e} {e['a_nodes']:9.2e} {e['p']:9.2e} {e['t']:9.2e}")
    for row in time_to_accuracy_rows(name, st["rows"]):
        print("  ", " | ".join(row))


if __name__ == "__main__":  # python -m verification.test_speed_accuracy [ci|full] [scene …]
    import sys
    sub = sys.argv[1] if len(sys.argv) > 1 else "ci"
    for nm in sys.argv[2:] or SCENES:
        t = time.perf_counter()
        print_study(nm, study(nm, sub))
        print(f"   total {time.perf_counter() - t:.1f} s")


# ----------------------------------------------------------------------------- tests
SERIES = (("gfmd-fire", 1e-8), ("gfmd-verlet", 1e-8), ("fe-p1", None), ("fe-p2", None))
SUBSET_TEXT = {"ci": "CI subset: GFMD FIRE/Verlet N = 64, 128, 256 × tolerance 1e-2, 1e-4, 1e-8; FE P1/P2 "
                     "N = 64, 128, 256; reference GFMD FIRE N = 1024, tolerance 1e-10",
               "full": "full sweep (--full): GFMD FIRE/Verlet N = 64 … 1024 × tolerance 1e-2, 1e-4, 1e-6, 1e-8; "
                       "FE P1/P2 N = 64 … 512; reference GFMD FIRE N = 4096, tolerance 1e-10"}


NOISE_FLOOR = 1e-6  # p error below which GFMD sits on its solver-tolerance plateau (see docstring)
MAX_REFINEMENT_RATIO = 1.0  # e_p(2N)/e_p(N) above the floor: strictly decreasing
RATIO_SOURCE = ("study in the module docstring: every series decreases strictly (worst measured ratio 0.94, P1 "
                "nearing its mesh floor); errors below 1e-6 are GFMD's tolerance plateau (1e-8 × p_ref gives "
                "2e-9 … 1.3e-7) and are not compared")
#: (scene, subset) -> bound on the p(δ) rel. L2 difference FE P2 vs GFMD FIRE (tol 1e-8) at FE's finest N
AGREEMENT = {("adhesive-sinusoid", "ci"): 5.6e-5, ("adhesive-sinusoid", "full"): 2.4e-6,
             ("adhesive-self-affine", "ci"): 1.0e-3, ("adhesive-self-affine", "full"): 9.5e-5,
             ("hard-wall-self-affine", "ci"): 3.9e-3, ("hard-wall-self-affine", "full"): 3.8e-4}
AGREEMENT_SOURCE = "3× the difference measured in the study (module docstring)"
REFERENCE_TEXT = ("GFMD FIRE at tolerance 1e-10 on the finest grid (no analytic solution exists for these three "
                  "scenes). GFMD is the most accurate available run: its p(δ) converges spectrally on the two "
                  "adhesive scenes (2e-9 at N = 256) and with order ≈ 1.7 on the hard wall, and it is the only "
                  "method that reaches N_ref = 1024/4096 in < 1 s (FE P2 is 1.5–3× more accurate than GFMD at "
                  "equal N on the hard wall only).")


def refinement_series(rows, method, tolerance, metric="p"):
    """[(N, error)] of one method at one tolerance, by increasing N."""
    return sorted((s.nodes, e[metric]) for s, _, e, _ in rows if s.method == method and s.tolerance == tolerance)


def worst_refinement_ratio(series, floor):
    """max over consecutive N of e(2N)/e(N), pairs whose finer error is below `floor` (noise) skipped."""
    ratios = [b / a for (_, a), (_, b) in zip(series, series[1:]) if b > floor]
    return max(ratios) if ratios else 0.0


def finest(rows, method, tolerance):
    best = max((s.nodes, r) for s, _, e, r in rows if s.method == method and s.tolerance == tolerance)
    return best


def sweep_plots(name, st, subset):
    rows = st["rows"]
    ref_s, ref_wall, _ = st["reference"]
    plots = []
    for metric, what in (("p", "p(δ) relative L2 error"), ("a", "max |a_rel − a_ref|"),
                         ("t", "t_n rel. L2 (last step)")):
        points = [{"label": s.label, "method": s.method, "time": wall, "error": e[metric]}
                  for s, wall, e, _ in rows]
        plots.append(harness.pareto_plot(points, ylabel=what, title=f"{name}: {what} vs wall time ({subset})"))
    table = [[s.label, f"{wall:.3g}", f"{e['a']:.2e}", f"{e['a_nodes']:.2e}", f"{e['p']:.2e}", f"{e['t']:.2e}"]
             for s, wall, e, _ in rows]
    plots.append(harness.table_plot(["setting", "wall s", "|Δa_rel|", "|Δa_rel| (ref. on the nodes)", "p rel. L2",
                                     "t_n rel. L2"], table,
                                    title=f"{name}: all settings vs reference {ref_s.label} ({ref_wall:.2f} s)"))
    plots.append(harness.table_plot(["scene", "target", "GFMD needs", "FE needs"],
                                    time_to_accuracy_rows(name, rows),
                                    title=f"{name}: cheapest setting below 1 % error (0.1 % in p), wall time"))
    return plots


@pytest.mark.parametrize("subset", ["ci", pytest.param("full", marks=pytest.mark.slow)])
@pytest.mark.parametrize("name", list(SCENES))
def test_speed_accuracy(name, subset, verification_record):
    t0 = time.perf_counter()
    st = study(name, subset)
    wall = time.perf_counter() - t0
    print_study(name, st)
    rows = st["rows"]
    ref_s = st["reference"][0]
    case = f"speed-accuracy/{name}"
    methods = tuple(sorted({s.method for s, *_ in rows}))
    res = {"subset": subset, "reference": ref_s.label}
    notes = SUBSET_TEXT[subset] + ". Reference: " + REFERENCE_TEXT + " Timings: one run, shared machine."
    verification_record(case=case, metric=f"speed–accuracy sweep ({subset}): settings run", value=len(rows),
                        tolerance=None, passed=None, methods=methods, tolerance_source="informational",
                        resolution=res, wall_s=wall, plots=sweep_plots(name, st, subset), notes=notes,
                        scene=SCENES[name](ref_s.nodes))
    # 1. errors decrease with refinement, per method (monotone within the noise)
    worst, failures = 0.0, []
    for method, tol in SERIES:
        series = refinement_series(rows, method, tol)
        ratio = worst_refinement_ratio(series, NOISE_FLOOR)
        worst = max(worst, ratio)
        if ratio > MAX_REFINEMENT_RATIO or not series[-1][1] < series[0][1]:
            failures.append(f"{method}: p errors {[f'{e:.2g}' for _, e in series]} (N = {[n for n, _ in series]})")
    verification_record(case=case, metric="worst e_p(2N)/e_p(N) over the methods", value=worst,
                        tolerance=MAX_REFINEMENT_RATIO, methods=methods, tolerance_source=RATIO_SOURCE,
                        resolution=res, notes=notes, passed=not failures)
    # 2. the most refined GFMD and FE P2 agree
    n_g, rg = finest(rows, "gfmd-fire", 1e-8)
    n_f, rf = finest(rows, "fe-p2", None)
    if n_g != n_f:  # full sweep: GFMD goes further; compare on FE's finest grid
        n_g, rg = n_f, next(r for s, _, _, r in rows if s.method == "gfmd-fire" and s.tolerance == 1e-8
                            and s.nodes == n_f)
    dp = harness.relative_l2(rf.curve["p"], rg.curve["p"], rg.curve["p"])
    da = float(np.max(np.abs(rf.curve["a_rel"] - rg.curve["a_rel"])))
    bound = AGREEMENT[(name, subset)]
    print(f"FE P2 vs GFMD FIRE at N = {n_f}: p rel. L2 {dp:.3g}, max |Δa_rel| {da:.3g}; worst ratio {worst:.3g}")
    verification_record(case=case, metric=f"p(δ) rel. L2, FE P2 vs GFMD FIRE at N = {n_f}", value=dp,
                        tolerance=bound, methods=("gfmd-fire", "fe-p2"), tolerance_source=AGREEMENT_SOURCE,
                        resolution=dict(res, N=n_f), notes=notes)
    verification_record(case=case, metric=f"max |Δa_rel|, FE P2 vs GFMD FIRE at N = {n_f}", value=da,
                        tolerance=4 / n_f, methods=("gfmd-fire", "fe-p2"),
                        tolerance_source="a few contact-edge nodes may flip: 4/N", resolution=dict(res, N=n_f),
                        notes=notes)
    assert not failures, "errors do not decrease with refinement: " + "; ".join(failures)
    assert dp <= bound, f"FE P2 and GFMD differ by {dp:.3g} in p(δ) at N = {n_f} (bound {bound:.3g})"
    assert da <= 4 / n_f + 1e-12, f"FE P2 and GFMD differ by {da:.3g} in a_rel at N = {n_f}"


def test_time_to_one_percent(verification_record):
    """Summary table over the three scenes (CI subset; the studies are cached from test_speed_accuracy)."""
    rows = []
    for name in SCENES:
        rows += time_to_accuracy_rows(name, study(name, "ci")["rows"])
    for r in rows:
        print(" | ".join(r))
    verification_record(case="speed-accuracy/summary", metric="time to reach 1 % error (CI subset)",
                        value=len(rows), tolerance=None, passed=None, tolerance_source="informational",
                        methods=("gfmd-fire", "gfmd-verlet", "fe-p1", "fe-p2"), resolution={"subset": "ci"},
                        notes=SUBSET_TEXT["ci"] + ". Reference: " + REFERENCE_TEXT,
                        plots=[harness.table_plot(["scene", "target", "GFMD needs", "FE needs"], rows,
                                                  title="to reach 1 % error (0.1 % in p): GFMD needs X s, FE needs Y s "
                                                        "(cheapest setting, CI subset, one run)")])
    assert all(len(r) == 4 for r in rows)
