"""3-D FE surface stiffness of the periodic bonded cell against reference-formulas §1.3.

The FE's mode stiffness Ŝ(m, n)/W (Pa/m, `reference.fem3d.assembly`) for single Fourier modes
against the layer's normal-only stiffness k_zz^eff(|q|) (§1.3, `gfmd_contact.core.kernels.layer_normal`: a
verification test may use the kernels the FE must not), and the half-space E*|q|/2 it approximates
for D ≥ the cell size with the truncation error k_layer/k_half − 1 (stated in the data file).
Mesh family: N × N surface nodes, N/2 layers down to D = L graded geometrically with a fixed total
growth (bottom/top thickness) GROWTH = 8, i.e. the fixed map z = −D (8^ξ − 1)/7 sampled at ξ = k/(N/2),
so that every spacing halves with l = L/N. The measured relative errors and observed orders are in verification/data/mesh/fem3d_stiffness.json
(`python tests/test_fem3d_stiffness.py` rewrites it, N = 8, 16, 32, 64); the tests recompute the
small meshes and hold them to those numbers and to Q1's order 2.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core.kernels import layer_normal
from reference.fem3d.assembly import build_cell, direct_surface_column

DATA = Path(__file__).resolve().parent.parent / "verification" / "data" / "mesh" / "fem3d_stiffness.json"
E, NU, L = 1.0, 0.3, 1.0
MODES = [(1, 0), (1, 1), (2, 0), (4, 0)]
GROWTH = 8.0
E_STAR = E / (1 - NU**2)
M_OVER_D = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / L


def family_cell(n):
    layers = n // 2
    ratio = GROWTH ** (1 / layers)
    return build_cell(n, n, L, L, L, E, NU, layers=layers, top=L * (ratio - 1) / (GROWTH - 1))


def mode_errors(n):
    """{mode: FE stiffness / layer formula − 1} for the family mesh with N = n."""
    cell = family_cell(n)
    k_fe = cell.mode_stiffness / cell.weights[0]
    out = {}
    for m, k in MODES:
        q = 2 * np.pi * np.hypot(m, k) / L
        out[f"{m},{k}"] = float(k_fe[m, k] / layer_normal(np.array([q]), E, NU, L)[0] - 1)
    return out, cell


def measure(sizes=(8, 16, 32, 64)):
    errors, dofs, layers = {}, {}, {}
    for n in sizes:
        errors[n], cell = mode_errors(n)
        dofs[n], layers[n] = cell.dofs, cell.layers
    orders = {mode: [float(np.log2(abs(errors[a][mode] / errors[b][mode]))) for a, b in zip(sizes, sizes[1:])]
              for mode in errors[sizes[0]]}
    truncation = {f"{m},{k}": float(layer_normal(np.array([2 * np.pi * np.hypot(m, k) / L]), E, NU, L)[0]
                                    / (E_STAR * np.pi * np.hypot(m, k) / L) - 1) for m, k in MODES}
    return {"E": E, "nu": NU, "L": L, "D": L, "sizes": list(sizes), "layers": layers, "dofs": dofs,
            "relative_error_vs_layer": errors, "observed_order": orders,
            "halfspace_truncation_k_layer_over_k_half_minus_1": truncation,
            "note": "N×N surface nodes, N/2 layers graded with total growth 8 down to D = L; Q1 hexahedra, nodal quadrature"}


@pytest.fixture(scope="module")
def data():
    return json.loads(DATA.read_text())


def test_mode_stiffness_reproduces_the_measured_errors(data):
    """N = 8, 16 recomputed: the same errors as measured (round-off of a deterministic assembly)."""
    for n in (8, 16):
        errors, _ = mode_errors(n)
        for mode, e in errors.items():
            assert e == pytest.approx(data["relative_error_vs_layer"][str(n)][mode], rel=1e-8, abs=1e-13)


def test_mode_stiffness_converges_at_order_two(data):
    """Q1 with nodal quadrature: error O(l²). The measured order approaches 2 (the finest pair no farther
    from 2 than the coarsest) and is 2 to one decimal at the finest pair."""
    for mode, orders in data["observed_order"].items():
        assert abs(orders[-1] - 2) <= abs(orders[0] - 2) + 1e-12, (mode, orders)
        assert round(orders[-1], 1) == 2.0, (mode, orders)
    # the errors decrease monotonically on the family
    for mode in data["observed_order"]:
        e = [abs(data["relative_error_vs_layer"][str(n)][mode]) for n in data["sizes"]]
        assert all(a > b for a, b in zip(e, e[1:])), (mode, e)


def test_uniform_compression_is_exact():
    """The q = 0 mode of a laterally periodic bonded layer is uniaxial strain: M/D, exact for Q1 (linear
    field) up to round-off, on any grading."""
    for n, layers in ((4, 3), (8, 5)):
        cell = build_cell(n, n + 2, L, 1.3 * L, 0.7 * L, E, NU, layers=layers)
        m_over_d = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / (0.7 * L)
        assert cell.mode_stiffness[0, 0] / cell.weights[0] == pytest.approx(m_over_d, rel=1e-12)


def test_circulant_condensation_equals_the_sparse_direct_solve():
    """The Fourier-block condensation gives the column of S the full sparse system gives (SuperLU)."""
    cell = build_cell(6, 4, L, 0.8 * L, 0.9 * L, E, NU, layers=4)
    direct = direct_surface_column(6, 4, L, 0.8 * L, cell.z_levels, E, NU)
    assert np.max(np.abs(cell.surface_column() - direct)) <= 1e-12 * np.max(np.abs(direct))


def test_surface_weights_are_the_node_area():
    cell = build_cell(5, 7, L, 1.4 * L, L, E, NU)
    assert np.allclose(cell.weights, (L / 5) * (1.4 * L / 7), rtol=1e-13)


if __name__ == "__main__":
    DATA.write_text(json.dumps(measure(), indent=1) + "\n")
    print(DATA.read_text())
