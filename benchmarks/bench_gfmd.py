"""GFMD cost per load step vs N, in units of one FFT pair measured in the same run.

Usage: python benchmarks/bench_gfmd.py [--quick] [--out DIR]

For N = 2^10 … 2^17 (--quick: … 2^14), each interface (hard wall; cohesive
φn* = 0.01; cohesive φn* = 0.15) and each method (fire, verlet) it times
warm-started load steps of a displacement ramp at relative tolerance 1e-10 and
prints / writes (CSV + markdown, into benchmarks/results/):

  time per step, iterations per step, FFT pairs per step, and
  ratio = (time per step) / (time of one scipy.fft rfft+irfft pair at that N).

The machine is shared and noisy (2 cores, other jobs): only the ratio, whose
numerator and denominator are measured in the same process within seconds of
each other, is meant to be compared between runs.

Scene (units SI, gfmd_contact.core.conventions): the default scene's self-affine surface
(H = 0.8, h_rms = 10 nm, ν = 0.45, L = 1.28 µm, L/λr = 8) with the short
cut-off λs,H = max(4 l, L/4096): 4 nodes per shortest wavelength up to
N = 2^14, and from N = 2^15 on the fixed surface of the seed's discretisation
(λr/λs,H = 512, λs,H = 32 l at N = 2^17).

Ramp: an untimed coarse approach (1 nm increments from first touch, tolerance
1e-6, FIRE) to δ = 20 nm, then the default scene's increment dU = 27 nm / 80 with
tolerance 1e-10. The first two fine steps are untimed (they set up the linear
extrapolation guess 2u_k − u_{k−1} used by gfmd.loading); the next STEPS steps
are timed. Both methods start every timed step from the same guess (built from
the FIRE-converged previous steps), so a capped Verlet step does not contaminate
the next one.

Verlet is capped: max_iterations is set so that one step takes at most about
VERLET_SECONDS (from the measured pair time); a capped step is marked in the
table ("capped", residual given) and its time is a lower bound.

Hard wall + verlet: timed since solver 13e5ae4 (before it, the hard-wall routine
ignored the method and ran FIRE).

FFT pairs per iteration are counted once (N = 1024) by wrapping scipy.fft.rfft /
irfft with counters (wrappers are not active during the timed runs).
"""

from __future__ import annotations

import argparse
import csv
import datetime
import os
import platform
import sys
import time
from pathlib import Path

# BLAS threads: OpenBLAS's thread pool on a loaded 2-core machine made length-N dot
# products cost milliseconds (thread hand-off), up to 100x the arithmetic; the solver
# now avoids BLAS for them, and the benchmark pins BLAS to one thread anyway (as CI
# does) unless --blas-default-threads is given. It must happen *before* numpy is
# imported, hence the late imports below (E402).
if "--blas-default-threads" not in sys.argv:
    for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import numpy as np
import scipy
import scipy.fft

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script from anywhere

# the project's imports follow the thread settings and the path (noqa: E402), on purpose
from gfmd import fft as gfft  # noqa: E402
from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import indenter_surface  # noqa: E402
from gfmd_contact.core.model import build_model  # noqa: E402
from gfmd_contact.core.scene import default_scene  # noqa: E402
from gfmd.solver import InterfaceLaw, Settings, relax  # noqa: E402

TOLERANCE = 1e-10
STEPS = 3  # timed steps per (N, law, method)
DELTA_START = 20e-9  # m, penetration at which the timed window starts
D_U = 27e-9 / 80  # m, default-scene increment
LAWS = (("hard-wall", 0.0), ("cohesive", 0.01), ("cohesive", 0.15))
METHODS = ("fire", "verlet")


def machine_info():
    cpu = platform.processor() or ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = os.getloadavg()
    except OSError:
        load = (float("nan"),) * 3
    return {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "host": platform.node(), "cpu": cpu, "cores": os.cpu_count(),
        "python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
        "loadavg_start": " ".join(f"{v:.2f}" for v in load),
        "OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS", "(unset: library default)"),
        "scipy.fft workers": 1,
        "gfmd": _gfmd_version(),
    }


def _gfmd_version():
    """git commit of the checkout, '+dirty' if gfmd/ has uncommitted changes, and solver.py's hash."""
    import hashlib
    import subprocess
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True,
                              text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "gfmd"], cwd=root, capture_output=True,
                               text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        head, dirty = "?", ""
    sha = hashlib.sha1((root / "gfmd" / "solver.py").read_bytes()).hexdigest()[:10]
    return f"{head}{'+dirty' if dirty else ''} (solver.py sha1 {sha})"


def pair_time(n, backend="scipy", min_seconds=0.3, min_reps=30):
    """Median wall time (s) of one rfft + irfft pair of a real array of length n."""
    rfft, irfft = (scipy.fft.rfft, scipy.fft.irfft) if backend == "scipy" else (np.fft.rfft, np.fft.irfft)
    x = np.random.default_rng(0).standard_normal(n)
    for _ in range(3):
        irfft(rfft(x), n=n)
    samples, total = [], 0.0
    while total < min_seconds or len(samples) < min_reps:
        t = time.perf_counter()
        irfft(rfft(x), n=n)
        dt = time.perf_counter() - t
        samples.append(dt)
        total += dt
    return float(np.median(samples))


def scene_at(n, law, phi):
    length = 1.28e-6
    kw = {"surface.nodes": n, "surface.length": length, "surface.rolloff_wavelength": length / 8,
          "surface.rollon_wavelength": max(4 * length / n, length / 4096), "interface.law": law}
    if law == "cohesive":
        kw["interface.phi_n_star"] = phi
    return default_scene().replace(**kw)


class Case:
    """Model, law and indenter of one (N, law), with helpers to relax a step."""

    def __init__(self, n, law, phi):
        self.scene = scene_at(n, law, phi)
        self.h = surfaces.profile(self.scene.surface, 0)
        self.model = build_model(self.scene, self.h)
        self.law = InterfaceLaw(self.model, self.scene.interface, self.scene.work_tangential)
        self.wall_tol = 1e-12 * max(float(np.ptp(self.h)), self.scene.interface.length_normal)
        self.d0 = self.scene.loading.initial_separation

    def z(self, delta):
        return indenter_surface(self.h, self.d0, delta + self.d0)

    def relax(self, delta, guess, settings):
        return relax(self.model, self.law, self.z(delta), guess, settings, self.wall_tol)


def approach(case):
    """Untimed coarse approach to DELTA_START − 2 dU; returns the converged u_hat there."""
    coarse = Settings(method="fire", tolerance=1e-6)
    u = np.zeros((case.model.components, case.model.nodes // 2 + 1), complex)
    for delta in np.arange(-case.d0, DELTA_START - 2 * D_U, 1e-9):
        r = case.relax(delta, u, coarse)
        if not r.converged:
            raise RuntimeError(f"approach step δ = {delta:.3g} m did not converge: {r.message}")
        u = r.u_hat
    return u


def count_pairs_per_iteration(case, u, method):
    """FFT pairs (rfft + irfft calls / 2) per iteration of one step, counted with wrappers."""
    calls = {"n": 0}
    orig = scipy.fft.rfft, scipy.fft.irfft

    def wrap(f):
        def g(*a, **k):
            calls["n"] += 1
            return f(*a, **k)
        return g

    scipy.fft.rfft, scipy.fft.irfft = wrap(orig[0]), wrap(orig[1])
    try:
        r = case.relax(DELTA_START, u, Settings(method=method, tolerance=TOLERANCE, max_iterations=400))
    finally:
        scipy.fft.rfft, scipy.fft.irfft = orig
    assert gfft.scipy.fft.rfft is orig[0]
    if r.fft_pairs:  # the hard-wall CG counts its own pairs (whatever the FFT backend)
        return r.fft_pairs / max(r.iterations, 1)
    return calls["n"] / 2 / r.iterations


def run(quick, out_dir, verlet_seconds):
    info = machine_info()
    exps = range(10, 15 if quick else 18)
    print("# GFMD benchmark " + ("(quick)" if quick else "(full)"))
    print("# " + ", ".join(f"{k}: {v}" for k, v in info.items()), flush=True)

    # pairs per iteration, counted at N = 1024 (independent of N)
    ppi = {}
    for law, phi in LAWS:
        case = Case(1024, law, phi)
        u = approach(case)
        for method in METHODS:
            ppi[(law, phi, method)] = count_pairs_per_iteration(case, u, method)

    rows, fft_rows = [], []
    t_all = time.perf_counter()
    for e in exps:
        n = 2**e
        t_pair = pair_time(n)
        t_np = pair_time(n, "numpy")
        fft_rows.append({"N": n, "scipy_pair_s": t_pair, "numpy_pair_s": t_np, "numpy/scipy": t_np / t_pair})
        pair_samples = [t_pair]
        block = []
        for law, phi in LAWS:
            case = Case(n, law, phi)
            t0 = time.perf_counter()
            u = approach(case)
            # two untimed fine steps, then the timed window; keep FIRE-converged states
            fine = Settings(method="fire", tolerance=TOLERANCE)
            prev = u
            r = case.relax(DELTA_START - D_U, u, fine)
            u = r.u_hat
            guesses = []
            for k in range(STEPS):
                delta = DELTA_START + k * D_U
                guess = 2 * u - prev
                guesses.append((delta, guess))
                r = case.relax(delta, guess, fine)
                if not r.converged:
                    raise RuntimeError(f"FIRE step N={n} {law} δ={delta:.3g}: {r.message}")
                prev, u = u, r.u_hat
            setup = time.perf_counter() - t0
            law_name = "hard-wall" if law == "hard-wall" else f"cohesive {phi:g}"
            fire_s_per_it = None
            for method in METHODS:
                if method == "verlet":
                    # cap from the measured FIRE cost per iteration (≈ Verlet's: one pair + law)
                    cap = int(np.clip(verlet_seconds / fire_s_per_it, 1000, 200_000))
                    settings = Settings(method=method, tolerance=TOLERANCE, max_iterations=cap)
                else:
                    cap = None
                    settings = fine
                times, its, res, conv = [], [], [], []
                for delta, guess in guesses:
                    t = time.perf_counter()
                    r = case.relax(delta, guess, settings)
                    times.append(time.perf_counter() - t)
                    its.append(r.iterations)
                    res.append(r.residual)
                    conv.append(r.converged)
                if method == "fire":
                    fire_s_per_it = sum(times) / sum(its)
                pair_samples.append(pair_time(n, min_seconds=0.1, min_reps=20))
                note = "" if all(conv) else f"capped at {cap} it ({sum(not c for c in conv)}/{len(conv)} steps)"
                block.append({"N": n, "method": method, "law": law_name, "time_s": float(np.median(times)),
                              "iterations": float(np.median(its)), "pairs_per_it": ppi[(law, phi, method)],
                              "max_residual": float(max(res)), "converged": f"{sum(conv)}/{len(conv)}",
                              "note": note})
            print(f"  N={n} {law_name}: setup {setup:.1f} s", flush=True)
        t_pair_med = float(np.median(pair_samples))
        for row in block:
            row["pair_s"] = t_pair_med
            if "time_s" in row:
                row["fft_pairs"] = row["iterations"] * row["pairs_per_it"]
                row["ratio"] = row["time_s"] / t_pair_med
                row["overhead"] = row["ratio"] / row["fft_pairs"]
            print(format_row(row), flush=True)
        rows += block
    info["loadavg_end"] = " ".join(f"{v:.2f}" for v in os.getloadavg())
    info["total_s"] = f"{time.perf_counter() - t_all:.0f}"
    write(out_dir, "quick" if quick else "full", info, rows, fft_rows, verlet_seconds)


COLUMNS = ("N", "method", "law", "time_s", "iterations", "fft_pairs", "ratio", "overhead", "pair_s",
           "max_residual", "converged", "note")


def fmt(v):
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def format_row(row):
    return " | ".join(fmt(row.get(c, "")) for c in COLUMNS)


def write(out_dir, tag, info, rows, fft_rows, verlet_seconds):
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(out_dir / f"bench_gfmd_{tag}.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        for k, v in info.items():
            w.writerow([f"# {k}", v])
        w.writerow(COLUMNS)
        for row in rows:
            w.writerow([row.get(c, "") for c in COLUMNS])
    lines = [f"# GFMD benchmark ({tag})", "",
             "Machine: " + "; ".join(f"{k} = {v}" for k, v in info.items()), "",
             f"Warm-started steps (dU = {D_U * 1e9:.4g} nm at δ ≈ {DELTA_START * 1e9:g} nm, extrapolated guess), "
             f"relative tolerance {TOLERANCE:g}, median of {STEPS} steps. ratio = time per step / time of one "
             "scipy.fft rfft+irfft pair at that N (same run); fft_pairs = iterations × counted pairs per "
             "iteration; overhead = ratio / fft_pairs. Verlet capped at about "
             f"{verlet_seconds:g} s per step (max_iterations from the pair time): capped rows give lower bounds.",
             "", "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + format_row(row) + " |" for row in rows]
    lines += ["", "FFT pair time, scipy.fft vs numpy.fft (median, s):", "",
              "| N | scipy | numpy | numpy/scipy |", "|---|---|---|---|"]
    lines += [f"| {r['N']} | {r['scipy_pair_s']:.3g} | {r['numpy_pair_s']:.3g} | {r['numpy/scipy']:.2f} |"
              for r in fft_rows]
    text = "\n".join(lines) + "\n"
    (out_dir / f"bench_gfmd_{tag}.md").write_text(text)
    print(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="N up to 2^14 (< 3 min)")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    ap.add_argument("--blas-default-threads", action="store_true",
                    help="leave BLAS threading to the environment/library default (default: pinned to 1)")
    ap.add_argument("--verlet-seconds", type=float, default=None,
                    help="cap on one Verlet step (s); default 2 (quick) or 3 (full)")
    a = ap.parse_args(argv)
    vs = a.verlet_seconds if a.verlet_seconds is not None else (2.0 if a.quick else 3.0)
    run(a.quick, a.out, vs)


if __name__ == "__main__":
    main()
