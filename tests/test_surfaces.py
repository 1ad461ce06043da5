"""Tests of gfmd_contact.core.surfaces: indenter profiles h(x) (seed Eq. 4, reference-formulas §6).

The two-sided discrete PSD is ⟨|ĥ_n|²⟩ ∝ C(q_n) with ĥ = rfft(h)/N. Eq. 4 is transcribed here
independently of the code (`_eq4`).
"""

import math

import numpy as np
import pytest
import scipy.fft
from hypothesis import given, settings, strategies as st

from gfmd_contact.core import surfaces
from gfmd_contact.core.scene import Surface

EPS = np.finfo(float).eps

# the default scene's ratios: L/λr = 8, λr/λs,H = 64 (N = 4096, λs,H = 8 l)
N, L = 4096, 1.28e-6
LR, LSH = L / 8, L / 512


def _eq4(q, hurst, lr, lsh, length):
    """Seed Eq. 4 / C(q_r): 1 for λr < 2π/q ≤ L, (q/q_r)^{−(1+2H)} for λs,H ≤ 2π/q ≤ λr (the
    upper end as in reference-formulas §6), 0 above q_s = 2π/λs,H and at q = 0."""
    q = np.asarray(q, float)
    out = np.zeros_like(q)
    with np.errstate(divide="ignore"):
        wavelength = 2 * np.pi / q
    q_r = 2 * np.pi / lr
    rel = 1e-12  # wavelengths computed from q carry round-off
    plateau = (wavelength > lr * (1 + rel)) & (wavelength <= length * (1 + rel))
    power = (wavelength >= lsh * (1 - rel)) & (wavelength <= lr * (1 + rel))
    out[plateau] = 1.0
    out[power] = (q[power] / q_r) ** (-(1 + 2 * hurst))
    return out


def _spectrum(h):
    return np.abs(scipy.fft.rfft(h) / h.size) ** 2


def _q(nodes, length):
    return 2 * np.pi * np.fft.rfftfreq(nodes, d=length / nodes)


# ---------------------------------------------------------------- grid and PSD shape

def test_grid():
    x = surfaces.grid(8, 4.0)
    assert np.array_equal(x, np.array([-4, -3, -2, -1, 0, 1, 2, 3]) * 0.5)
    assert surfaces.grid(9, 9.0)[9 // 2] == 0.0  # x = 0 is node N//2 for odd N too
    assert np.allclose(np.diff(surfaces.grid(100, 1e-6)), 1e-8, rtol=1e-12, atol=0)


@pytest.mark.parametrize("hurst", [0.2, 0.5, 0.8])
def test_psd_shape_function_is_eq4(hurst):
    q = _q(N, L)
    c = surfaces.psd_self_affine(q, hurst, LR, LSH, L)
    assert np.allclose(c, _eq4(q, hurst, LR, LSH, L), rtol=1e-13, atol=0)
    q_r, q_s = 2 * np.pi / LR, 2 * np.pi / LSH
    assert c[0] == 0.0  # no mean
    assert np.all(c[(q > 0) & (q < q_r)] == 1.0)  # flat roll-off plateau
    assert np.all(c[q > q_s * (1 + 1e-12)] == 0.0)  # cut above q(λs,H)
    # even in q (two-sided)
    assert np.array_equal(surfaces.psd_self_affine(-q, hurst, LR, LSH, L), c)


# ---------------------------------------------------------------- random profiles

hursts = st.floats(0.05, 0.95)
seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=25, derandomize=True, deadline=None)
@given(hursts, st.floats(1e-10, 1e-6), seeds, st.sampled_from([256, 1024, 1025]))
def test_exact_rms_and_zero_mean(hurst, h_rms, seed, nodes):
    length = 1e-6
    h = surfaces.self_affine(nodes, length, hurst, h_rms, length / 4, 4 * length / nodes, seed)
    assert h.shape == (nodes,) and np.all(np.isfinite(h))
    # exact after the final rescaling: round-off of a mean of squares and a sqrt (1e-12 as specified)
    assert math.sqrt(np.mean(h**2)) == pytest.approx(h_rms, rel=1e-12)
    assert abs(np.mean(h)) <= 1e-12 * h_rms  # no q = 0 mode: the mean is round-off only


def test_reproducible_for_equal_seed_and_different_otherwise():
    args = (N, L, 0.8, 1e-8, LR, LSH)
    a = surfaces.self_affine(*args, seed=7)
    assert np.array_equal(a, surfaces.self_affine(*args, seed=7))  # bit for bit
    b = surfaces.self_affine(*args, seed=8)
    # independent phases: the correlation of two realizations is O(1/√modes) ≈ 0.05, never ≈ 1
    assert not np.array_equal(a, b)
    assert abs(np.corrcoef(a, b)[0, 1]) < 0.5


@settings(max_examples=20, derandomize=True, deadline=None)
@given(hursts, seeds, st.sampled_from([512, 513, 2048]))
def test_no_content_above_rollon_at_zero_or_nyquist(hurst, seed, nodes):
    length = 2e-6
    lsh = 8 * length / nodes
    h = surfaces.self_affine(nodes, length, hurst, 1e-8, length / 8, lsh, seed)
    spec = _spectrum(h)
    q = _q(nodes, length)
    # irfft→rfft round trip leaves ≲ 1e-32 of the peak power in empty modes (measured 3e-32): 1e-26
    peak = spec.max()
    assert np.all(spec[q > 2 * np.pi / lsh * (1 + 1e-12)] <= 1e-26 * peak)
    assert spec[0] <= 1e-26 * peak
    if nodes % 2 == 0:
        assert spec[-1] <= 1e-26 * peak


def test_nyquist_mode_empty_even_when_the_cutoff_allows_it():
    # λs,H = 2l puts q_s on the Nyquist mode: even N must still leave it empty (§6 step 1); odd N has none
    nodes, length = 256, 1e-6
    h = surfaces.self_affine(nodes, length, 0.5, 1e-8, length / 4, 2 * length / nodes, seed=1)
    spec = _spectrum(h)
    assert spec[-1] <= 1e-26 * spec.max()
    assert spec[-2] > 1e-6 * spec.max()  # its neighbour does carry power


@pytest.mark.parametrize("hurst", [0.2, 0.5, 0.8])
def test_periodogram_follows_eq4(hurst):
    # every mode: |ĥ_n|² / |ĥ(q_r)|² = C(q_n)/C(q_r) (amplitudes are deterministic, §6 step 1–4),
    # round-off level (1e-10 covers the FFT round trip, measured ≲ 1e-13 relative)
    h = surfaces.self_affine(N, L, hurst, 1e-8, LR, LSH, seed=11)
    spec = _spectrum(h)
    q = _q(N, L)
    shape = _eq4(q, hurst, LR, LSH, L)
    n_r = int(round(L / LR))
    ratio = spec / spec[n_r]
    live = shape > 0
    assert np.allclose(ratio[live], shape[live], rtol=1e-10, atol=0)
    assert np.all(ratio[~live] <= 1e-26)


# Scatter study for the fitted slope (this file's author, seeds 1000·rep + i, rep = 0…29, i = 0…7;
# N = 4096, L/λr = 8, λr/λs,H = 64, 505 modes in [q_r, q_s], M = 8 realizations averaged):
#   H     mean(slope) + (1 + 2H)    std over the 30 repetitions
#   0.2   1.3e-15                   7.0e-17
#   0.5   4.4e-16                   1.3e-16
#   0.8   8.9e-16                   8.9e-16
# The scatter is round-off because the amplitudes are deterministic (only the phases are random,
# reference-formulas §6). |bias| + 10·std ≤ 1e-14; the tolerance 1e-12 keeps a ×100 margin for other
# FFT back-ends and is still 1e-10 of the smallest exponent change a wrong H would give.
SLOPE_TOL = 1e-12


@pytest.mark.parametrize("hurst", [0.2, 0.5, 0.8])
def test_fitted_powerlaw_slope(hurst):
    realizations = 8
    power = np.mean([_spectrum(surfaces.self_affine(N, L, hurst, 1e-8, LR, LSH, seed=500 + i))
                     for i in range(realizations)], axis=0)
    q = _q(N, L)
    fit = (q >= 2 * np.pi / LR * (1 - 1e-12)) & (q <= 2 * np.pi / LSH * (1 + 1e-12))
    assert fit.sum() == 505
    slope = np.polyfit(np.log(q[fit]), np.log(power[fit]), 1)[0]
    assert abs(slope + (1 + 2 * hurst)) <= SLOPE_TOL
    # and the plateau below q_r is flat (zero slope, same round-off argument)
    flat = (q > 0) & (q < 2 * np.pi / LR * (1 - 1e-12))
    assert np.ptp(np.log(power[flat])) <= SLOPE_TOL


def test_heights_are_close_to_gaussian():
    # seed: Gaussian height distribution. Scatter study (100 sets of 8 realizations, H = 0.8, the few
    # plateau modes dominate): skewness 0.003 ± 0.126 (max |.| 0.39), excess kurtosis −0.08 ± 0.20
    # (max |.| 0.68). The bound 1 is ≥ 5 std; non-random phases (e.g. all equal: a spike) give ≫ 10.
    h = np.concatenate([surfaces.self_affine(N, L, 0.8, 1e-8, LR, LSH, seed=s) for s in range(8)])
    z = h / h.std()
    assert abs(np.mean(z**3)) < 1.0
    assert abs(np.mean(z**4) - 3) < 1.0


def test_empty_spectrum_is_an_error():
    # roll-off and roll-on both longer than the cell: no mode q_n ≥ 2π/L is in the spectrum
    with pytest.raises(ValueError, match="no modes"):
        surfaces.self_affine(64, 1.0, 0.5, 1e-9, 2.0, 1.5, seed=0)


# ---------------------------------------------------------------- deterministic shapes

@pytest.mark.parametrize("nodes", [8, 64, 65])
def test_sinusoid(nodes):
    a, length = 5e-9, 1e-6
    h = surfaces.sinusoid(nodes, length, a)
    x = surfaces.grid(nodes, length)
    assert np.allclose(h, -a * np.cos(2 * np.pi * x / length), rtol=0, atol=4 * EPS * a)
    assert h[nodes // 2] == -a and np.argmin(h) == nodes // 2  # first contact at x = 0
    assert abs(np.mean(h)) <= 16 * EPS * a
    assert math.sqrt(np.mean(h**2)) == pytest.approx(a / math.sqrt(2), rel=1e-14)  # exact for N ≥ 3
    if nodes % 2 == 0:
        assert h[0] == pytest.approx(a, rel=1e-15)  # x = −L/2: the crest, peak-to-valley 2a


@pytest.mark.parametrize("nodes", [8, 64, 65])
def test_cylinder(nodes):
    radius, length = 1e-6, 4e-7
    h = surfaces.cylinder(nodes, length, radius)
    x = surfaces.grid(nodes, length)
    assert h[nodes // 2] == 0.0 and np.all(h >= 0)
    assert np.allclose(h, x**2 / (2 * radius), rtol=4 * EPS, atol=0)
    # symmetric about x = 0
    j = np.arange(1, (nodes - 1) // 2)
    assert np.array_equal(h[nodes // 2 + j], h[nodes // 2 - j])


def test_flat():
    h = surfaces.flat(16, 1e-6)
    assert h.shape == (16,) and np.all(h == 0.0)


# ---------------------------------------------------------------- file profiles

@pytest.mark.parametrize("suffix", [".npy", ".txt", ".dat"])
def test_from_file_round_trip(tmp_path, suffix):
    heights = np.random.default_rng(0).normal(0, 1e-8, 32)
    path = tmp_path / f"h{suffix}"
    if suffix == ".npy":
        np.save(path, heights)
    else:
        np.savetxt(path, heights, fmt="%.17g")  # 17 digits: exact float round trip
    assert np.array_equal(surfaces.from_file(path, 32), heights)
    assert np.array_equal(surfaces.from_file(str(path), 32), heights)


@pytest.mark.parametrize("count", [31, 33, 1])
def test_from_file_wrong_length(tmp_path, count):
    path = tmp_path / "h.npy"
    np.save(path, np.zeros(count))
    with pytest.raises(ValueError) as info:
        surfaces.from_file(path, 32)
    message = str(info.value)
    assert "surface.path" in message and str(path) in message
    assert f"{count} heights" in message and "surface.nodes = 32" in message


def test_from_file_missing_and_non_finite(tmp_path):
    with pytest.raises(ValueError, match="no such file"):
        surfaces.from_file(tmp_path / "absent.npy", 8)
    path = tmp_path / "bad.txt"
    np.savetxt(path, [0.0, 1e-9, np.nan, 0.0, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="non-finite"):
        surfaces.from_file(path, 8)


def _write(directory, what):
    """A file that is not a profile of 256 heights; returns (path, words the message must hold)."""
    d = directory
    if what == "16x16 npy":  # 256 values, accepted as a 256-node profile before
        np.save(d / "h.npy", np.zeros((16, 16)))
        return d / "h.npy", ["(16, 16)", "2-D"]
    if what == "corrupt npy":
        (d / "h.npy").write_bytes(b"\x93NUMPY\x01\x00" + b"\x00" * 40)
        return d / "h.npy", ["not a valid .npy file"]
    if what == "text named npy":
        (d / "h.npy").write_text("1e-9\n" * 256)
        return d / "h.npy", ["not a valid .npy file"]
    if what == "npz named npy":
        np.savez(d / "h.npz", h=np.zeros(256))
        (d / "h.npz").rename(d / "h.npy")
        return d / "h.npy", ["NpzFile", "not an array"]
    if what == "0-d npy":
        np.save(d / "h.npy", np.float64(1e-9))
        return d / "h.npy", ["0-D"]
    if what == "empty npy":
        np.save(d / "h.npy", np.zeros(0))
        return d / "h.npy", ["empty"]
    if what == "complex npy":
        np.save(d / "h.npy", np.zeros(256, complex))
        return d / "h.npy", ["complex128", "not real numbers"]
    if what == "string npy":
        np.save(d / "h.npy", np.array(["1e-9"] * 256))
        return d / "h.npy", ["not real numbers"]
    if what == "comma-separated":
        (d / "h.csv").write_text("\n".join(f"{i},1e-9" for i in range(128)) + "\n")
        return d / "h.csv", ["comma-separated"]
    if what == "comma row":
        (d / "h.txt").write_text(",".join(["1e-9"] * 256) + "\n")
        return d / "h.txt", ["comma-separated"]
    if what == "empty text":
        (d / "h.txt").write_text("")
        return d / "h.txt", ["empty"]
    if what == "comments only":
        (d / "h.txt").write_text("# heights in m\n\n")
        return d / "h.txt", ["empty"]
    if what == "two columns":
        np.savetxt(d / "h.txt", np.zeros((128, 2)))
        return d / "h.txt", ["(128, 2)", "2-D"]
    if what == "header word":
        (d / "h.txt").write_text("height\n" + "0\n" * 256)
        return d / "h.txt", ["cannot be read as numbers", "height"]
    if what == "ragged":
        (d / "h.txt").write_text("1 2\n3\n")
        return d / "h.txt", ["cannot be read as numbers"]
    if what == "binary":
        (d / "h.dat").write_bytes(bytes(range(256)) * 4)
        return d / "h.dat", ["binary content", "SurfaceTopography cannot read it", ".npy"]  # an instrument format?
    if what == "directory":
        (d / "h.npy").mkdir()
        return d / "h.npy", ["directory"]
    raise AssertionError(what)


BAD_FILES = ["16x16 npy", "corrupt npy", "text named npy", "npz named npy", "0-d npy", "empty npy", "complex npy",
             "string npy", "comma-separated", "comma row", "empty text", "comments only", "two columns",
             "header word", "ragged", "binary", "directory"]


@pytest.mark.parametrize("what", BAD_FILES)
def test_from_file_refuses_what_is_not_a_profile(tmp_path, what):
    # a SceneError (a ValueError) naming surface.path, the file, the problem and what is expected,
    # never a raw numpy/pickle/unicode error or a silently flattened array
    from gfmd_contact.core.scene import SceneError

    path, words = _write(tmp_path, what)
    with pytest.raises(SceneError) as info:
        surfaces.from_file(path, 256)
    message = str(info.value)
    assert message.startswith(f"surface.path = {str(path)!r}: "), message
    if what != "binary":  # binary content is an instrument file's, whatever its suffix: its refusal says so
        assert "expected a 1-D .npy array or a text file with one column of surface.nodes = 256 heights in m" in message
    for word in words:
        assert word in message, message
    assert "\n" not in message and len(message) < 400, message


def test_from_file_accepts_integers_and_one_row(tmp_path):
    np.save(tmp_path / "i.npy", np.arange(16))
    assert np.array_equal(surfaces.from_file(tmp_path / "i.npy", 16), np.arange(16.0))
    (tmp_path / "row.txt").write_text(" ".join(["2e-9"] * 16) + "  # one line is one 1-D row\n")
    assert np.array_equal(surfaces.from_file(tmp_path / "row.txt", 16), np.full(16, 2e-9))


# ---------------------------------------------------------------- dispatch from a scene spec

def test_profile_dispatch(tmp_path):
    spec = Surface(kind="self-affine", length=L, nodes=1024, hurst=0.5, h_rms=2e-9,
                   rolloff_wavelength=LR, rollon_wavelength=LSH, seed=4, realizations=3)
    for i in range(3):  # realization i uses seed + i
        expected = surfaces.self_affine(1024, L, 0.5, 2e-9, LR, LSH, seed=4 + i)
        assert np.array_equal(surfaces.profile(spec, i), expected)
    assert np.array_equal(surfaces.profile(spec), surfaces.profile(spec, 0))
    assert np.array_equal(surfaces.profile(Surface(kind="sinusoid", length=L, nodes=64, amplitude=3e-9)),
                          surfaces.sinusoid(64, L, 3e-9))
    assert np.array_equal(surfaces.profile(Surface(kind="cylinder", length=L, nodes=64, radius=1e-5)),
                          surfaces.cylinder(64, L, 1e-5))
    assert np.array_equal(surfaces.profile(Surface(kind="flat", length=L, nodes=64)), np.zeros(64))
    path = tmp_path / "h.npy"
    np.save(path, np.arange(64.0))
    assert np.array_equal(surfaces.profile(Surface(kind="file", length=L, nodes=64, path=str(path))),
                          -np.arange(64.0))  # a measured surface, its summits facing the body
    assert np.array_equal(surfaces.profile(Surface(kind="file", length=L, nodes=64, path=str(path),
                                                   facing="valleys")), np.arange(64.0))  # the heights as they are
    with pytest.raises(ValueError, match="surface.kind"):
        surfaces.profile(Surface(kind="fractal", length=L, nodes=64))
