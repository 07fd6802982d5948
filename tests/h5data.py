"""Comparing HDF5 datasets in tests: every array of a file, and two files' equality."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np


def datasets(path: Path) -> dict[str, np.ndarray]:
    """Every dataset of an HDF5 file, by path, read into memory."""
    out: dict[str, np.ndarray] = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset)
                     else None)
    return out


def assert_same_data(a: Path, b: Path) -> None:
    """The two files hold the same datasets with equal values."""
    da, db = datasets(a), datasets(b)
    assert sorted(da) == sorted(db)
    for key in da:
        np.testing.assert_array_equal(da[key], db[key], err_msg=key)
