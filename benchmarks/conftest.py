"""The benchmark suite's sizes, shared cases and summary table (pytest-benchmark).

Run from the repository root: ``python -m pytest benchmarks`` (small sizes, a few minutes on 2 cores) or
``python -m pytest benchmarks --full`` (the paper's sizes). ``benchmarks/pytest.ini`` makes this directory its
own pytest root, so the repository's ``pytest`` (testpaths tests, verification) never runs a benchmark.

After the run a table prints one row per benchmark: the time per load step (the fastest round), the FFT pairs the
step used, the step's time in units of one rfft+irfft pair at the same size (measured in the same process: the number to
compare between machines and runs on a shared, noisy one) and, for the hard wall, the ratio to Tamaas on the same
load where Tamaas is installed.
"""

from __future__ import annotations

import os
import platform
import time
from dataclasses import dataclass, field

# one BLAS/OpenMP thread, as the study workers run, before numpy loads BLAS (the suite's timings are single-threaded)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

#: per size option: 1+1-D exponents e of N = 2^e, 2+1-D nodes per side, FE nodes, the study task's (exponent, steps),
#: rounds per benchmark
SIZES = {
    "small": {"exponents": (12, 14), "side": 128, "fe_nodes": 256, "task": (12, 40), "rounds": 5},
    "full": {"exponents": (14, 17), "side": 512, "fe_nodes": 1024, "task": (17, 40), "rounds": 5},
}


def pytest_addoption(parser):
    try:
        parser.addoption("--full", action="store_true", default=False, help="the paper's sizes (2^14 and 2^17, 512²)")
    except ValueError:  # run together with the repository's tests: its conftest's --full (a flag too) serves
        pass
    parser.addoption("--exponents", default=None,
                     help="comma-separated exponents e of the 1+1-D sizes N = 2^e (default: of the size option)")


def sizes_of(config):
    """The sizes dict of the run: SIZES' small or full, the 1+1-D exponents replaced by --exponents where given."""
    sizes = dict(SIZES["full" if config.getoption("--full") else "small"])
    text = config.getoption("--exponents")
    if text:
        try:
            sizes["exponents"] = tuple(int(e) for e in text.split(","))
        except ValueError:
            raise pytest.UsageError(f"--exponents {text!r}: expected comma-separated integers, e.g. 12,14") from None
    return sizes


def pytest_generate_tests(metafunc):
    """`exponent` parameters: the run's 1+1-D sizes."""
    if "exponent" in metafunc.fixturenames:
        metafunc.parametrize("exponent", sizes_of(metafunc.config)["exponents"], ids=lambda e: f"2^{e}")


@pytest.fixture(scope="session")
def sizes(pytestconfig):
    return sizes_of(pytestconfig)


def pair_seconds(n, grid=None, reps=None):
    """The fastest wall time (s) of one rfft + irfft pair through `gfmd.fft.Fft` (the default backend) on n nodes."""
    from gfmd.fft import Fft

    fft = Fft(n, grid=grid)
    x = fft.empty_nodes() if grid is None else np.empty(n)
    x[:] = np.random.default_rng(0).standard_normal(n)
    for _ in range(3):
        fft.irfft(fft.rfft(x))
    samples = []
    for _ in range(reps or max(20, int(4e6 // n))):
        t = time.perf_counter()
        fft.irfft(fft.rfft(x))
        samples.append(time.perf_counter() - t)
    return float(np.min(samples))


@dataclass
class Row:
    name: str
    size: str
    seconds: float | None  # per load step (s), the fastest round; None where timing was disabled
    pairs: float | None = None  # FFT pairs per step
    pair_s: float | None = None  # one pair at this size (s), same process
    tamaas_s: float | None = None  # Tamaas on the same load (s)
    note: str = ""


@dataclass
class Table:
    rows: list = field(default_factory=list)
    pairs: dict = field(default_factory=dict)  # size label -> one pair's seconds
    tamaas: dict = field(default_factory=dict)  # size label -> Tamaas' seconds on the hard wall's step
    extra: dict = field(default_factory=dict)  # what one benchmark's note compares with another's

    def pair(self, label, n, grid=None):
        """One FFT pair's seconds at this size, measured now (just before the row that divides by it: the speed of a
        shared machine drifts within seconds)."""
        self.pairs[label] = pair_seconds(n, grid)
        return self.pairs[label]

    def add(self, benchmark, name, size, per=1, **kw):
        """A row from the benchmark's fastest round (divided by `per`: the load steps one timed call ran): the robust
        estimate on a shared machine, whose other jobs only ever add time."""
        stats = getattr(benchmark, "stats", None)
        seconds = stats.stats.min / per if stats is not None else None
        self.rows.append(Row(name, size, seconds, **kw))
        benchmark.extra_info.update({k: v for k, v in kw.items() if v is not None})

    def lines(self):
        head = ("| benchmark | size | ms per step (fastest) | FFT pairs per step | step / FFT pair | GFMD / Tamaas "
                "| note |",
                "|---|---|---|---|---|---|---|")
        return [*head, *(self._line(r) for r in self.rows)]

    def _line(self, r):
        ms = f"{r.seconds * 1e3:.3g}" if r.seconds is not None else "–"
        pairs = f"{r.pairs:.0f}" if r.pairs is not None else "–"
        ratio = f"{r.seconds / r.pair_s:.0f}" if r.seconds is not None and r.pair_s else "–"
        tam = self.tamaas.get(r.size) if r.name == "hard wall" else None
        vs = f"{r.seconds / tam:.2f}" if tam and r.seconds is not None else "–"
        return f"| {r.name} | {r.size} | {ms} | {pairs} | {ratio} | {vs} | {r.note} |"


@pytest.fixture(scope="session")
def table(pytestconfig):
    t = Table()
    pytestconfig.stash[TABLE] = t
    return t


TABLE = pytest.StashKey[Table]()


def pytest_terminal_summary(terminalreporter, config):
    t = config.stash.get(TABLE, None)
    if t is None or not t.rows:
        return
    cpu = next((line.split(":", 1)[1].strip() for line in _cpuinfo() if line.startswith("model name")),
               platform.processor())
    terminalreporter.section("gfmd-contact benchmarks")
    terminalreporter.write_line(f"{cpu}, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}; "
                                f"sizes {'full' if config.getoption('--full') else 'small'}")
    for line in t.lines():
        terminalreporter.write_line(line)


def _cpuinfo():
    try:
        with open("/proc/cpuinfo") as fh:
            return fh.read().splitlines()
    except OSError:
        return []
