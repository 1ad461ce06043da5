"""Mutation score: does `pytest verification` alone catch single-point physics bugs?

Each mutation (`MUTATIONS`) replaces one exact snippet of the source by a wrong one (a kernel
1 % stiffer, the coupling sign flipped, the law's exponent changed, p scaled by 1.01, ...).
`run` copies the working tree (tracked and untracked, not ignored files) to a temporary
directory, applies one mutation there, runs `python -m pytest verification -x` in the copy
(the copy's packages shadow the installed ones: the working directory comes first on sys.path)
and records whether the suite failed (caught), which test failed first and how long it took.
An unmutated run must pass first, or nothing is measured.

    python -m verification.mutations [--only ID ...] [--ref REV] [--key NAME] [--write]

prints the table; `--write` stores it in verification/data/mutations.json, which the report
shows ("Mutation score"). CI runs a representative few (tests/test_mutations.py); the whole
list takes about one verification run per mutation.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from verification import measured

NAME = "mutations"
ROOT = Path(__file__).resolve().parent.parent


@dataclass(frozen=True)
class Mutation:
    id: str
    path: str | tuple  # relative to the repository root; a tuple: the snippet's sites spread over these files
    old: str  # exact snippet (must occur `count` times in all)
    new: str
    what: str
    count: int = 1

    @property
    def paths(self):
        return (self.path,) if isinstance(self.path, str) else tuple(self.path)


MUTATIONS = (
    Mutation("surface-qy", "gfmd_contact/core/kernels.py",
             "    qy = 2.0 * np.pi * np.fft.rfftfreq(nodes_y, d=length_y / nodes_y)",
             "    qy = 2.02 * np.pi * np.fft.rfftfreq(nodes_y, d=length_y / nodes_y)",
             "2+1-D: the y wavenumbers 1 % high (GFMD's surface kernel)"),
    Mutation("surface-gradient-y", "gfmd_contact/core/observables.py", "        return parts[0] + parts[1]",
             "        return parts[0] + 1.02 * parts[1]", "2+1-D: the y part of the local |∇h|² 2 % high (ḡ_r, ḡ)"),
    Mutation("kernel-scale", "gfmd_contact/core/kernels.py",
             "return 0.5 * contact_modulus(youngs_modulus, poisson_ratio) * np.abs(q)",
             "return 0.505 * contact_modulus(youngs_modulus, poisson_ratio) * np.abs(q)",
             "half-plane normal kernel 1 % stiffer"),
    Mutation("coupling-sign", "gfmd_contact/core/kernels.py", "    k_xz = 1j * beta * s * f", "    k_xz = -1j * beta * s * f",
             "sign of the half-plane normal–tangential coupling flipped"),
    Mutation("layer-q0", "gfmd_contact/core/kernels.py", "    k[zero] = constrained_modulus(youngs_modulus, nu) / thickness",
             "    k[zero] = 1.1 * constrained_modulus(youngs_modulus, nu) / thickness",
             "layer's uniform-mode (q = 0) stiffness M/D 10 % off"),
    Mutation("law-exponent", "gfmd_contact/core/law_equations.py", "return (work_normal / length_normal) * s * np.exp(-s)",
             "return (work_normal / length_normal) * s * np.exp(-1.05 * s)",
             "normal CZ traction: exponent e^(−s) → e^(−1.05 s)"),
    Mutation("contact-threshold", "gfmd_contact/core/law_equations.py", "    s = -lambertw(-contact_tolerance, k=-1).real\n    return s * length_normal",
             "    s = -lambertw(-contact_tolerance, k=-1).real\n    return 1.02 * s * length_normal",
             "cohesive contact gap threshold Δtol 2 % larger"),
    Mutation("gr-mean", "gfmd_contact/core/observables.py",
             "    return float(np.sqrt(np.mean(g2[contact])))",
             "    return float(np.mean(np.sqrt(g2[contact])))",
             "ḡ_r as the mean of |g| instead of the rms (seed Eq. 5)"),
    Mutation("eq6-stencil", "gfmd_contact/core/observables.py", "    backward = (h - np.roll(h, 1)) / spacing",
             "    backward = (h - np.roll(h, 2)) / spacing", "seed Eq. 6: backward difference off by one node"),
    Mutation("p-scale", "gfmd_contact/core/observables.py", "    return float(-np.mean(traction_z))",
             "    return float(-1.01 * np.mean(traction_z))", "mean pressure p scaled by 1.01"),
    Mutation("stop-early-cohesive", ("gfmd/algorithms/dynamics.py", "gfmd/algorithms/ncg.py",
                                     "gfmd/algorithms/hard_wall_dynamics.py"),
             "/ model.reference_traction\n            if residual < options.tolerance:",
             "/ model.reference_traction\n            if residual < 1e4 * options.tolerance:",
             "GFMD cohesive FIRE (normal and coupled law), NCG and the FIRE hard wall stop at 10⁴ × their "
             "tolerance", count=3),
    Mutation("stop-early-hard-wall", "gfmd/chains.py",
             "    key = chain_key(problem, settings)\n",
             "    key = chain_key(problem, settings)\n"
             '    if key[1] in ("cg-dual2", "cg-dual"):\n'
             "        settings = replace(settings, tolerance=1e4 * settings.tolerance)\n",
             "GFMD hard-wall CG (dual and primal) stops at 10⁴ × its tolerance (and says it converged)"),
    Mutation("verlet-is-fire", ("gfmd/algorithms/dynamics.py", "gfmd/algorithms/hard_wall_dynamics.py"),
             'fire = None if options.method == "verlet" else Fire(options)',
             "fire = Fire(options)", "method verlet silently runs FIRE", count=2),
    Mutation("kappa-fit", "gfmd_contact/core/observables.py", "return float(x @ y / (x @ x)), int(use.sum())",
             "return 1.02 * float(x @ y / (x @ x)), int(use.sum())", "κ fit 2 % high"),
    Mutation("fe-quadrature", "reference/fem/assembly.py", "    np.add.at(w, pos, ones[top_s])",
             "    np.add.at(w, pos, np.full_like(ones[top_s], length / xs.size))",
             "FE surface quadrature weights uniform (L/points each) instead of the FacetBasis load vector "
             "(Simpson l/3, 2l/3 for P2; P1 unchanged)"),
    # the code every method shares (the shared ramp is checked, not trusted): caught by
    # verification/test_ramp_records.py, which recomputes the records from the saved fields
    Mutation("ramp-delta-off-by-one", "gfmd_contact/core/ramp.py", "delta=displacement - d0,",
             "delta=steps[max(k - 1, 0)] - d0,",
             "the ramp records δ of the previous step (bookkeeping off by one; the solve itself is right)"),
    Mutation("g-spacing", "gfmd_contact/core/observables.py",
             "    return float(np.sqrt(np.mean(local_gradient_squared(h, spacing, periodic))))",
             "    return float(np.sqrt(np.mean(local_gradient_squared(h, spacing * h.size / (h.size - 1), periodic))))",
             "whole-profile ḡ with the spacing L/(N − 1) instead of L/N"),
    Mutation("hysteresis-sign", "gfmd_contact/core/cycle.py",
             "    return float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(delta)))",
             "    return -float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(delta)))",
             "hysteresis W = ∮ p̄ dδ with its sign flipped"),
    Mutation("wall-leak", "gfmd/loading.py", "wall_tolerance = 1e-12 * max(", "wall_tolerance = 1e-3 * max(",
             "hard wall: nodes within 1e-3 of the profile span count as on the wall (a leak)"),
    # the suite's former blind spots, each caught by its own cross-check (named in the entry)
    Mutation("cycle-start-dropped", "gfmd_contact/core/cycle.py",
             "path = np.concatenate([[idx[0] - 1], idx]) if idx[0] > 0 else idx", "path = idx",
             "a second cycle starts at its own first step, not at the previous cycle's last (its W loses the "
             "first trapezoid, δ_start moves): verification/test_second_cycle.py"),
    Mutation("snap-off-first-jump", "gfmd_contact/core/cycle.py",
             'outs[-1]["delta_before"], outs[-1]["step"]', 'outs[0]["delta_before"], outs[0]["step"]',
             "snap-off at the first partial jump-out on unloading instead of the last (a rough surface detaching "
             "patch by patch): verification/test_snap_off_patches.py"),
    Mutation("kernel-ly-is-lx", "gfmd_contact/core/kernels.py", "rfftfreq(nodes_y, d=length_y / nodes_y)",
             "rfftfreq(nodes_y, d=length_x / nodes_y)",
             "2+1-D: the y wavenumbers built from Lx (right on a square cell only): "
             "verification/test_embedded_sinusoid_y.py"),
    Mutation("jkr-sphere-pull-off", "reference/analytic/jkr_sphere.py", "return -1.5 * math.pi * w * R,",
             "return -2.0 * math.pi * w * R,",
             "the JKR sphere reference's load-control pull-off −2πwR (DMT's) instead of −(3/2)πwR: "
             "verification/test_sphere_pull_off_references.py"),
    Mutation("persson-tosatti-half", "gfmd_contact/core/stickiness.py",
             "return 0.5 * float(np.sum(np.asarray(stiffness", "return 1.0 * float(np.sum(np.asarray(stiffness",
             "Persson–Tosatti θ: the full-contact elastic energy without its ½: "
             "verification/test_stickiness_numbers.py"),
    Mutation("user-law-tolerance-gap", "gfmd_contact/core/user_law.py",
             "target = self.contact_tolerance * np.e * self.peak_traction",
             "target = self.contact_tolerance * self.peak_traction",
             "a user law's traction-tolerance contact gap without the factor e (Δtol too far out): "
             "verification/test_user_law_contact_gap.py"),
)


def _tree_files(root):
    out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"], cwd=root,
                         capture_output=True, text=True, check=True).stdout
    return [f for f in out.split("\0") if f and (root / f).is_file()]


def copy_tree(root, dest, ref=None):
    """Copy the working tree's tracked and untracked (not ignored) files to `dest`, or with `ref`
    the files of that commit (`git archive`: a reproducible tree, untouched by uncommitted work)."""
    if ref is not None:
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "archive", "--format=tar", ref], cwd=root, capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive.stdout, check=True)
        return dest
    for f in _tree_files(root):
        target = dest / f
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(root / f, target)
    return dest


def apply(mutation, tree):
    """Apply `mutation` in the copied tree; ValueError if its snippet does not occur exactly `count` times
    (over all its files, each of which must hold it at least once)."""
    texts = {p: (tree / p).read_text() for p in mutation.paths}
    found = {p: t.count(mutation.old) for p, t in texts.items()}
    if sum(found.values()) != mutation.count or not all(found.values()):
        raise ValueError(f"{mutation.id}: the snippet occurs {sum(found.values())} times in "
                         f"{', '.join(mutation.paths)} ({found}), expected {mutation.count} (the source moved: update verification/mutations.py)")
    for p, t in texts.items():
        (tree / p).write_text(t.replace(mutation.old, mutation.new))


def run_suite(tree, timeout=1800, pytest_args=()):
    """(failed?, first failing test id or "", seconds) of `pytest verification -x` in `tree`."""
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "pytest", "verification", "-x", "-q", "-p", "no:cacheprovider",
                           f"--report-dir={tree / 'reports'}", *pytest_args], cwd=tree, capture_output=True,
                          text=True, timeout=timeout, env=env)
    seconds = time.perf_counter() - t0
    first = re.search(r"^(?:FAILED|ERROR) (\S+)", proc.stdout, re.M)
    return proc.returncode != 0, first.group(1) if first else "", seconds


def run(ids=None, pytest_args=(), progress=print, ref=None):
    """Rows {id, what, caught, first_failure, seconds} for the mutations `ids` (default all), on the
    working tree or on commit `ref`."""
    chosen = [m for m in MUTATIONS if ids is None or m.id in ids]
    unknown = set(ids or ()) - {m.id for m in MUTATIONS}
    if unknown:
        raise ValueError(f"unknown mutation(s) {sorted(unknown)}; known: {[m.id for m in MUTATIONS]}")
    if ref is not None:  # one commit for every copy, even if HEAD moves meanwhile
        ref = subprocess.run(["git", "rev-parse", ref], cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout.strip()
    with tempfile.TemporaryDirectory(prefix="gfmd-mutations-") as tmp:
        clean = copy_tree(ROOT, Path(tmp) / "clean", ref)
        failed, first, seconds = run_suite(clean, pytest_args=pytest_args)
        if failed:
            raise RuntimeError(f"the unmutated suite fails ({first}): fix it before measuring mutations")
        progress(f"unmutated: pass ({seconds:.0f} s)")
        rows = []
        for m in chosen:
            tree = copy_tree(ROOT, Path(tmp) / m.id, ref)
            apply(m, tree)
            caught, first, seconds = run_suite(tree, pytest_args=pytest_args)
            rows.append({"id": m.id, "what": m.what, "caught": caught, "first_failure": first,
                         "seconds": round(seconds, 1)})
            progress(f"{m.id}: {'caught by ' + first if caught else 'NOT caught'} ({seconds:.0f} s)")
            shutil.rmtree(tree, ignore_errors=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="mutation ids (default: all)")
    ap.add_argument("--ref", help="measure commit REF (git archive) instead of the working tree")
    ap.add_argument("--key", help="entry name in the data file (default: all / partial)")
    ap.add_argument("--write", action="store_true", help="store the table in verification/data/mutations.json")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    rows = run(args.only, ref=args.ref, progress=lambda line: print(line, flush=True))
    caught = sum(r["caught"] for r in rows)
    print(f"mutation score: {caught} of {len(rows)} caught by `pytest verification` alone "
          f"({time.perf_counter() - t0:.0f} s)")
    if args.write:
        key = args.key or ("all" if not args.only else "partial")
        entries = dict(measured.load(NAME)["entries"]) if measured.path(NAME).exists() else {}
        entries[key] = measured.make_entry({"rows": rows, "caught": caught, "total": len(rows)},
                                           scene="each case's own scenes", ref=args.ref or "working tree",
                                           wall_s=time.perf_counter() - t0)
        print(measured.write(NAME, entries, description="single-point physics mutations vs `pytest verification -x` "
                                                        "(CI subset)"))


if __name__ == "__main__":
    main()
