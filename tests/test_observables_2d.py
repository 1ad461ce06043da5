"""2+1-D observables (gfmd_contact.core.observables on (Nx, Ny) arrays): the four-neighbour local gradient,
ḡ, ḡ_r, p, a_rel of the embedded sinusoid against 1+1-D, and the periodic contact patch statistics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from gfmd_contact.core import surfaces, surfaces_2d
from gfmd_contact.core.observables import (contact_patches, local_gradient_squared, patch_statistics, rms_gradient,
                                 step_observables)
from gfmd_contact.core.scene import scene_from_dict


def _plane_wave(nx, ny, lx, ly, mx, my, a=1e-9):
    x, y = surfaces.grid(nx, lx), surfaces.grid(ny, ly)
    kx, ky = 2 * np.pi * mx / lx, 2 * np.pi * my / ly
    return a * np.cos(kx * x[:, None] + ky * y[None, :] + 0.3), a**2 * (kx**2 + ky**2) / 2, (kx, ky)


@pytest.mark.parametrize("mx, my", [(1, 0), (0, 2), (3, 1), (2, 5)])
def test_plane_wave_mean_gradient_converges_at_order_two(mx, my):
    """mean g² → ⟨|∇h|²⟩ = a²|k|²/2 (exact), with error Σ_a k_a²(k_a l_a)²/24·(1 − (k_a l_a)²/30 + …) per axis:
    the order observed from two resolutions is 2 up to (3/4)·(kl)²/(30 ln 2) ≤ 0.05 (kl)² (the next term of
    that expansion), kl the largest k_a l_a of the coarse grid. A rectangular cell with Nx ≠ Ny: a code that
    used lx along y (or dropped an axis) errs by O(1) and shows order ≈ 0."""
    lx, ly = 1e-6, 0.6e-6
    errors, kl = [], None
    for refine in (1, 2):
        nx, ny = 48 * refine, 40 * refine
        h, exact, (kx, ky) = _plane_wave(nx, ny, lx, ly, mx, my)
        g2 = float(np.mean(local_gradient_squared(h, (lx / nx, ly / ny))))
        errors.append(abs(g2 - exact))
        if refine == 1:
            kl = max(abs(kx) * lx / nx, abs(ky) * ly / ny)
    order = math.log2(errors[0] / errors[1])
    assert abs(order - 2) <= 0.05 * kl**2, (order, kl)


def test_plane_wave_along_x_in_2d_equals_the_profile_gradient():
    """Constant along y: the y differences vanish exactly, g² is the 1-D seed Eq. 6 column by column."""
    h1 = surfaces.sinusoid(64, 1e-6, 3e-9)
    h2 = surfaces_2d.embedded_sinusoid(64, 1e-6, 8, 3e-9)
    g2 = local_gradient_squared(h2, (1e-6 / 64, 1e-6 / 8))
    assert all(np.array_equal(g2[:, j], local_gradient_squared(h1, 1e-6 / 64)) for j in range(8))


def _scenes(law="cohesive", ny=8):
    surface = {"kind": "sinusoid", "nodes": 64, "length": 1e-6, "amplitude": 5e-9}
    one = scene_from_dict({"surface": surface, "interface": {"law": law}})
    two = scene_from_dict({"surface": {**surface, "nodes_y": ny, "length_y": 0.3e-6}, "interface": {"law": law}})
    return one, two


@pytest.mark.parametrize("law", ["cohesive", "hard-wall", "cohesive-wall"])
def test_embedded_sinusoid_gives_the_profile_observables(law):
    """Fields constant along y (the 1+1-D fields embedded) give the 1+1-D p, a_rel, ḡ_r, ḡ: a mean over Ny
    equal columns is the mean over one up to the summation's round-off, ≤ log2(NxNy) ulp (pairwise sum)."""
    one, two = _scenes(law)
    rng = np.random.default_rng(1)
    h1 = surfaces.profile(one.surface)
    gap1 = np.abs(rng.normal(0, 2e-8, 64)) * (rng.random(64) < 0.7)
    t1 = np.where(gap1 == 0, -rng.random(64) * 1e8, rng.random(64) * 1e7)
    ny = two.surface.nodes_y
    h2 = surfaces.profile(two.surface)
    assert np.array_equal(h2, np.repeat(h1[:, None], ny, axis=1))
    o1 = step_observables(one, h1, gap1, t1)
    o2 = step_observables(two, h2, np.repeat(gap1[:, None], ny, 1), np.repeat(t1[:, None], ny, 1))
    ulps = math.log2(64 * ny) * np.finfo(float).eps
    for key in ("p", "a_rel", "g_r", "g"):
        assert o2[key] == pytest.approx(o1[key], rel=ulps, abs=0), key
    assert 0 < o1["a_rel"] < 1


# ---------------------------------------------------------------- contact patches

def test_patches_merge_across_both_boundaries():
    c = np.zeros((10, 8), bool)
    c[0, 3] = c[9, 3] = True  # one patch cut by the x boundary
    c[5, 0] = c[5, 7] = c[4, 7] = True  # one cut by the y boundary
    c[0, 0] = c[9, 0] = c[0, 7] = c[9, 7] = True  # one at the four corners
    c[5, 4] = True  # one inside
    labels, count = contact_patches(c)
    assert count == 4
    assert contact_patches(c, periodic=False)[1] == 9
    assert set(np.unique(labels)) == {0, 1, 2, 3, 4}
    stats = patch_statistics(c, node_area=2.0)
    assert stats == {"patches": 4, "mean_patch_area": 2.0 * c.sum() / 4, "largest_patch_area": 8.0}
    assert patch_statistics(np.zeros((4, 4), bool), 1.0)["patches"] == 0
    assert contact_patches(np.ones((4, 4), bool))[1] == 1


@settings(max_examples=60, derandomize=True, deadline=None)
@given(st.integers(0, 2**31), st.floats(0.1, 0.7), st.integers(0, 20), st.integers(0, 20))
def test_patch_count_is_invariant_under_periodic_shifts(seed, density, sx, sy):
    """On a torus a patch does not care where the cell's boundary lies: rolling the map keeps the count
    and the areas (without the boundary merge a roll cutting a patch changes the count)."""
    c = np.random.default_rng(seed).random((16, 12)) < density
    labels, count = contact_patches(c)
    rolled_labels, rolled = contact_patches(np.roll(c, (sx, sy), axis=(0, 1)))
    assert rolled == count
    sizes = np.sort(np.bincount(labels.ravel())[1:])
    assert np.array_equal(sizes, np.sort(np.bincount(rolled_labels.ravel())[1:]))
    assert sizes.sum() == c.sum()
