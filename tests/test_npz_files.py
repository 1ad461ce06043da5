"""The run files' .npz writer (`gfmd_contact.app.checkpoints._npz_bytes`): what np.load gives back, and which members it
deflates (only those zlib shrinks: zeros, masks; float fields are stored)."""

import io
import zipfile

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from gfmd_contact.app import checkpoints


def _members(data):
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        return {i.filename: i.compress_type for i in zf.infolist()}


def test_float_fields_are_stored_and_zeros_deflated():
    rng = np.random.default_rng(3)
    arrays = {"gap": rng.normal(size=4096) * 1e-9, "u_x": np.zeros(4096), "mask": rng.random(4096) < 0.2,
              "step": np.int64(7), "text": np.array('{"method": "gfmd"}')}
    data = checkpoints._npz_bytes(arrays)
    kinds = _members(data)
    assert kinds["gap.npy"] == zipfile.ZIP_STORED
    assert kinds["u_x.npy"] == zipfile.ZIP_DEFLATED
    assert kinds["mask.npy"] == zipfile.ZIP_DEFLATED
    with np.load(io.BytesIO(data)) as z:
        assert sorted(z.files) == sorted(arrays)
        for name, value in arrays.items():
            assert np.array_equal(z[name], value) and z[name].dtype == np.asarray(value).dtype
    assert set(_members(checkpoints._npz_bytes(arrays, compress=False)).values()) == {zipfile.ZIP_STORED}


def test_same_arrays_same_bytes():
    arrays = {"a": np.arange(10.0), "b": np.zeros((3, 4), complex)}
    assert checkpoints._npz_bytes(arrays) == checkpoints._npz_bytes(dict(arrays))


@settings(max_examples=40, deadline=None)
@given(hnp.arrays(st.sampled_from([np.float64, np.complex128, np.int64, np.bool_]),
                  hnp.array_shapes(min_dims=0, max_dims=3, max_side=40)))
def test_any_array_round_trips(a):
    with np.load(io.BytesIO(checkpoints._npz_bytes({"x": a}))) as z:
        back = z["x"]
    assert back.dtype == a.dtype and back.shape == a.shape
    assert np.array_equal(back, a, equal_nan=True)
