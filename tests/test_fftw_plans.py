"""The FFTW backend (`gfmd.fft`): the transforms numpy's, the callers' arrays untouched, and measured plans kept as
wisdom so that another process makes the same plan (the same bits)."""

import os
import subprocess
import sys

import numpy as np
import pytest

from gfmd import fft as gfft

pytestmark = pytest.mark.skipif(gfft._pyfftw is None, reason="pyfftw not installed")


@pytest.fixture
def fresh_plans(monkeypatch, tmp_path):
    """No plan of this thread made before; wisdom in tmp_path; transforms from 512 points measured."""
    monkeypatch.setattr(gfft._FFTW_LOCAL, "plans", {}, raising=False)
    monkeypatch.setenv("GFMD_FFTW_WISDOM", str(tmp_path))
    monkeypatch.setattr(gfft, "FFTW_MEASURE_FROM", 512)
    return tmp_path


@pytest.mark.parametrize("shape, grid", [((1024,), None), ((2, 1024), None), ((96,), None), ((32 * 48,), (32, 48))])
def test_fftw_is_numpys_transform(fresh_plans, shape, grid):
    rng = np.random.default_rng(3)
    x = rng.standard_normal(shape)
    n = shape[-1]
    fft = gfft.Fft(n, "fftw", grid=grid)
    if grid is None:
        want = np.fft.rfft(x, axis=-1)
    else:
        want = np.fft.rfft2(x.reshape(grid)).reshape(-1)
    x_before = x.copy()
    got = fft.rfft(x)
    np.testing.assert_array_equal(x, x_before)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.max(np.abs(want)))
    spectrum = got.copy()
    back = fft.irfft(got)
    np.testing.assert_array_equal(got, spectrum)  # the caller's spectrum is not destroyed
    np.testing.assert_allclose(back, x, rtol=0, atol=1e-13)
    other = fft.rfft(2.0 * x)  # a result owns its memory: the next call leaves it alone
    np.testing.assert_array_equal(got, spectrum)
    np.testing.assert_allclose(other, 2.0 * spectrum, rtol=0, atol=1e-12 * np.max(np.abs(want)))
    if x.ndim == 1:
        kernel = rng.standard_normal(got.size)
        out = np.empty(x.size)
        fft.apply_to(kernel, x, out)
        direct = np.fft.irfft(kernel * np.fft.rfft(x)) if grid is None else \
            np.fft.irfft2(kernel.reshape(grid[0], -1) * np.fft.rfft2(x.reshape(grid)), s=grid).reshape(-1)
        np.testing.assert_allclose(out, direct, rtol=0, atol=1e-12 * np.max(np.abs(direct)))
    assert fft.pairs == (2.5 if x.ndim == 1 else 1.5)


_OTHER_PROCESS = """
import sys, numpy as np
from gfmd import fft as gfft
gfft.FFTW_MEASURE_FROM = 512
x = np.random.default_rng(5).standard_normal(2048)
y = gfft.Fft(2048, "fftw").rfft(x)
print(gfft._fftw_plans((2048,), (-1,)).planner)
sys.stdout.buffer.flush()
np.save(sys.argv[1], y)
"""


def test_measured_plans_are_kept_as_wisdom(fresh_plans):
    x = np.random.default_rng(5).standard_normal(2048)
    y = gfft.Fft(2048, "fftw").rfft(x)
    assert gfft._fftw_plans((2048,), (-1,)).planner == "FFTW_MEASURE"
    wisdom = gfft.wisdom_path()
    assert wisdom.parent == fresh_plans and wisdom.read_bytes().startswith(b"(fftw")
    small = gfft._fftw_plans((256,), (-1,))
    assert small.planner == "FFTW_ESTIMATE"  # below FFTW_MEASURE_FROM
    # another process reads the wisdom: the same plan, the same bits
    out = fresh_plans / "other.npy"
    run = subprocess.run([sys.executable, "-c", _OTHER_PROCESS, str(out)], capture_output=True, text=True,
                         env={**os.environ, "GFMD_FFTW_WISDOM": str(fresh_plans)}, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split()[0] == "FFTW_MEASURE"
    np.testing.assert_array_equal(np.load(out), y)


def test_corrupt_wisdom_is_replaced(fresh_plans):
    path = gfft.wisdom_path()
    path.write_bytes(b"not wisdom at all")
    gfft.Fft(1024, "fftw").rfft(np.ones(1024))
    assert gfft._fftw_plans((1024,), (-1,)).planner == "FFTW_MEASURE"
    assert path.read_bytes().startswith(b"(fftw")


@pytest.mark.parametrize("where", ["off", "file"])
def test_no_wisdom_file_means_estimated_plans(fresh_plans, monkeypatch, where):
    if where == "file":  # a directory that cannot be made: its parent is a file
        blocker = fresh_plans / "blocker"
        blocker.write_text("")
        monkeypatch.setenv("GFMD_FFTW_WISDOM", str(blocker / "wisdom"))
    else:
        monkeypatch.setenv("GFMD_FFTW_WISDOM", "off")
        assert gfft.wisdom_path() is None
    x = np.random.default_rng(2).standard_normal(1024)
    y = gfft.Fft(1024, "fftw").rfft(x)
    assert gfft._fftw_plans((1024,), (-1,)).planner == "FFTW_ESTIMATE"
    np.testing.assert_allclose(y, np.fft.rfft(x), rtol=0, atol=1e-12 * np.max(np.abs(y)))


def test_the_default_fft_is_fftw():
    """Where pyfftw is installed (a default dependency) the default backend is FFTW, measured the fastest: 0.79–0.88×
    ducc0's CPU on whole 2^17 ramps of each law and less time per pair at 2^17 on both shapes
    (docs/design/performance.md; `python -m pytest benchmarks` times the default's pair)."""
    pytest.importorskip("pyfftw")
    assert gfft.fft_backend("auto") == "fftw"


@pytest.mark.skipif(gfft.fcntl is None, reason="no fcntl (not POSIX)")
def test_no_file_locks_means_estimated_plans(fresh_plans, monkeypatch):
    """A file system without locks (flock raises, as on some network mounts): FFTW_ESTIMATE, not a crash."""
    def no_locks(*args):
        raise OSError(37, "No locks available")

    monkeypatch.setattr(gfft.fcntl, "flock", no_locks)
    x = np.random.default_rng(4).standard_normal(1024)
    y = gfft.Fft(1024, "fftw").rfft(x)
    assert gfft._fftw_plans((1024,), (-1,)).planner == "FFTW_ESTIMATE"
    np.testing.assert_allclose(y, np.fft.rfft(x), rtol=0, atol=1e-12 * np.max(np.abs(y)))


def test_plans_are_made_off_the_calling_thread_and_their_errors_raised_in_it(fresh_plans, monkeypatch):
    """FFTW plans in a helper thread (pyfftw releases the GIL there), so the calling thread takes signals while a
    plan takes minutes; the plan and its bits are those the calling thread would make; an error comes back to it."""
    import threading

    planned_in, original = [], gfft._with_wisdom

    def recording(plan):
        planned_in.append(threading.current_thread())
        return original(plan)

    monkeypatch.setattr(gfft, "_with_wisdom", recording)
    x = np.random.default_rng(6).standard_normal(2048)
    y = gfft.Fft(2048, "fftw").rfft(x)
    assert planned_in and planned_in[0] is not threading.current_thread()
    assert gfft._fftw_plans((2048,), (-1,)).planner == "FFTW_MEASURE"
    np.testing.assert_allclose(y, np.fft.rfft(x), rtol=0, atol=1e-12 * np.max(np.abs(y)))

    def failing(plan):
        raise RuntimeError("planner failed")

    monkeypatch.setattr(gfft, "_with_wisdom", failing)
    with pytest.raises(RuntimeError, match="planner failed"):
        gfft.Fft(4096, "fftw").rfft(np.ones(4096))
    monkeypatch.setattr(gfft, "_with_wisdom", original)
    assert gfft.Fft(4096, "fftw").rfft(np.ones(4096))[0] == 4096  # the planning lock was let go


_PLANS_A_LARGE_TRANSFORM = """
import numpy as np
from gfmd import fft as gfft
print("planning", flush=True)
gfft.Fft(1 << 20, "fftw").rfft(np.ones(1 << 20))
print("planned", flush=True)
"""


def test_ctrl_c_is_honoured_within_a_second_while_fftw_plans(fresh_plans):
    """FFTW_MEASURE at 2^20 points plans for 84 s on the 2-core development machine (docs/design/preflight.md),
    all in C; SIGINT waited for it. Now the process ends within a second of the signal."""
    import signal
    import time

    proc = subprocess.Popen([sys.executable, "-c", _PLANS_A_LARGE_TRANSFORM], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, "GFMD_FFTW_WISDOM": str(fresh_plans)})
    assert proc.stdout.readline().strip() == "planning"
    time.sleep(1.0)
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail("SIGINT not honoured within 30 s while FFTW plans")
    latency = time.perf_counter() - sent
    if "planned" in out:
        pytest.skip("this machine planned 2^20 points within a second: nothing to interrupt")
    assert "KeyboardInterrupt" in err, err
    assert latency < 1.5, latency
    assert proc.returncode == 130, (proc.returncode, err)  # not SIGSEGV: the plan goes on while the process ends
