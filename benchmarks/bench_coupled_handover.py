"""The coupled chain's FIRE→Newton handover vs the "newton" chain on the Fig. 8 coupled ramp (issue 24).

Usage: python benchmarks/bench_coupled_handover.py [--sizes 13 14] [--realizations 0 1] [--max-steps K]
                                                   [--handover 1e-4] [--variants handover handover-near]

The coupled class of bench_adhesion_scaling (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, until a_rel ≥ 0.5),
realization i = profile seed 1 + i, each chain its own ramp in the same run (warm-up of 3 steps each, untimed):
the "newton" chain (Settings.coupled = "newton", the default before session 26) and the handover chains
("handover": Newton from FIRE's state at Settings.coupled_handover kept where near and locally stable;
"handover-near", the default since: near only). FFT pairs include the
stability test's (`gfmd.coupled_stability`, not in `Relaxed.fft_pairs`: counted here, column "stab").
Event steps: those the continuation Newton does not finish (label ≠ "newton"). Per step the variant's p and a_rel
are compared with the "newton" chain's, and (N ≤ 2^14) the largest nodal |Δu| / δn between the accepted states.
Writes benchmarks/results/bench_coupled_handover_<tag>.md.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_adhesion_scaling as bas  # noqa: E402
import bench_coupled_ptc as ptc  # noqa: E402  (its stability-test pair counter)
from gfmd import chains  # noqa: E402

_calls = []  # per chains.relax call: (stability-test FFT pairs, converged)


def _relax(*args, _inner=chains.relax, **kwargs):
    ptc._stability_pairs[0] = 0.0
    r = _inner(*args, **kwargs)
    _calls.append((ptc._stability_pairs[0], r.converged))
    return r


chains.coupled_stability = ptc._counted_stability  # counts the stability test's FFT pairs
bas.relax = _relax


def run(n, realization, options, max_steps):
    """Rows of one ramp with the stability pairs per step ("stab") added to "pairs"."""
    bas.ramp(n, "coupled", options, max_steps=3)  # warm-up
    _calls.clear()
    t0 = time.process_time()
    rows = bas.ramp(n, "coupled", options, max_steps, 1 + realization, keep_u_hat=n <= 2**14)
    cpu = time.process_time() - t0
    calls = iter(list(_calls))
    for r in rows:
        stab, ok = next(calls)
        if not ok and r["it"] > 0:  # a retry from the last converged state (bas.ramp): same step
            extra = next(calls, None)
            stab += extra[0] if extra else 0.0
        r["stab"] = stab
        r["pairs"] += stab
        r["event"] = r["method"] != "newton"
    return rows, cpu


def tolerance_bound(n, realization):
    """Two states with max nodal residual < tolerance·p_ref differ by less than this (in δn; the bound of
    tests/test_coupled_ptc.py: 10 · 2 tol p_ref √N / k1, k1 the lowest mode's smallest diagonal stiffness
    less its coupling, plus 1e-6 δn)."""
    base = bas.load_scene(bas.SEED / "seed_base.toml")
    rollon = max(base.surface.rollon_wavelength, bas.ROLLON_NODES * base.surface.length / n)
    scene = bas.task_scene(base.replace(**{"surface.nodes": n, "surface.rollon_wavelength": rollon,
                                           **bas.CLASSES["coupled"]}), realization)
    cell = bas.prepare(scene, bas.surfaces.profile(scene.surface, 0))
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    dn = scene.interface.length_normal
    return (20 * cell.settings.tolerance * m.reference_traction * np.sqrt(m.nodes) / k1 + 1e-6 * dn) / dn


TABLE = ["| N | real. | chain | steps | event steps | FFT pairs total | of which stab | pairs on event steps | "
         "CPU s ramp | max |Δp|/max p | a_rel differs at | max |Δu|/δn (bound) | labels |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]


def table_row(e, realization, name, rows, cpu, ref, bound):
    """One row of TABLE: the ramp `rows` of chain `name` at N = 2^e against the reference ramp `ref`."""
    dp, da, du = compare(ref, rows, 2**e)
    ev = [r for r in rows if r["event"]]
    labels = "/".join(sorted({r["method"] for r in rows}))
    return (f"| 2^{e} | {realization} | {name} | {len(rows)} | {len(ev)} | {sum(r['pairs'] for r in rows):.0f} | "
            f"{sum(r['stab'] for r in rows):.0f} | {sum(r['pairs'] for r in ev):.0f} | {cpu:.1f} | "
            f"{dp:.2g} | {da or '—'} | {'not kept' if du is None else f'{du:.2g}'} ({bound:.2g}) | {labels} |")


def parser(description):
    """The arguments the coupled-chain benchmarks share: --sizes, --realizations, --max-steps, --handover, --out."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--sizes", type=int, nargs="+", default=[13, 14])
    ap.add_argument("--realizations", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--max-steps", type=int, default=None)
    ap.add_argument("--handover", type=float, default=1e-4)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    return ap


def code_version():
    """"git <commit>", with "(+ uncommitted changes)" where gfmd/ differs from it."""
    commit = os.popen(f"git -C {ROOT} rev-parse --short HEAD").read().strip()
    dirty = " (+ uncommitted changes)" if os.popen(f"git -C {ROOT} status --porcelain gfmd").read().strip() else ""
    return f"git {commit}{dirty}"


def write(args, stem, lines):
    """benchmarks/results/<stem>_e<sizes>_r<realizations>.md (args.out) from the report's lines."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tag = "e" + "_".join(map(str, args.sizes)) + "_r" + "_".join(map(str, args.realizations))
    path = out / f"{stem}_{tag}.md"
    path.write_text("\n".join(lines) + "\n")
    print(f"wrote {path}")


def compare(ref, rows, n):
    """Per-step differences from the "newton" chain: max |Δp|/max|p|, steps with a_rel differing, max nodal |Δu| / δn."""
    dp, da, du, steps = 0.0, [], None, min(len(ref), len(rows))
    pscale = max(abs(r["p"]) for r in ref)
    for a, b in zip(ref[:steps], rows[:steps]):
        dp = max(dp, abs(a["p"] - b["p"]) / pscale)
        if a["a_rel"] != b["a_rel"]:
            da.append(a["k"])
        if "u_hat" in a:
            du = max(du or 0.0, float(np.max(np.abs(np.fft.irfft(a["u_hat"] - b["u_hat"], n)))) / 1e-9)  # δn = 1 nm
    return dp, da, du


def main(argv=None):
    ap = parser(__doc__.splitlines()[0])
    ap.add_argument("--variants", nargs="+", default=["handover", "handover-near"])
    args = ap.parse_args(argv)
    head = [f"`python benchmarks/bench_coupled_handover.py {' '.join(argv or sys.argv[1:])}`; {code_version()}; "
            f"handover residual {args.handover:g} p_ref, COUPLED_HANDOVER_MOVE = {chains.COUPLED_HANDOVER_MOVE}; load "
            f"average at start {os.getloadavg()[0]:.2f} (2-core machine shared with a full-scale study: CPU s under "
            "load, FFT pairs deterministic up to ARPACK's random start in the stability test)", ""]
    table = list(TABLE)
    detail = []
    for e in args.sizes:
        n = 2**e
        for real in args.realizations:
            variants = [("newton", {"coupled": "newton"})] + [(v, {"coupled": v, "coupled_handover": args.handover})
                                                       for v in args.variants]
            results, bound = {}, tolerance_bound(n, real)
            for name, options in variants:
                rows, cpu = run(n, real, options, args.max_steps)
                results[name] = rows
                line = table_row(e, real, name, rows, cpu, results["newton"], bound)
                table.append(line)
                print(line, flush=True)
            names = [v[0] for v in variants]
            detail += [f"### 2^{e}, realization {real}: event steps", "",
                       "| step | " + " | ".join(f"{v}: it / pairs (stab) / label" for v in names) + " |",
                       "|---|" + "---|" * len(names)]
            events = sorted({r["k"] for v in names for r in results[v] if r["event"]})
            for k in events:
                cells = []
                for v in names:
                    r = next((x for x in results[v] if x["k"] == k), None)
                    cells.append("—" if r is None else f"{r['it']} / {r['pairs']:.0f} ({r['stab']:.0f}) / {r['method']}")
                detail.append(f"| {k} | " + " | ".join(cells) + " |")
            detail.append("")
    write(args, "bench_coupled_handover", head + table + ["", f"Load average at end: {os.getloadavg()[0]:.2f}.", ""]
          + detail)


if __name__ == "__main__":
    main()
