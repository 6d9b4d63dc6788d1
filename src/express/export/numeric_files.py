"""Numerical matrices as ``.mat`` (MATLAB 5) and ``.npz`` bytes, byte-identical run to run.

``scipy.io.savemat`` stamps the creation time into the MAT header and ``numpy.savez``
the time into every zip entry; both are replaced by fixed values here so that the same
model gives the same file (the project's rule for exports).

Examples
--------
>>> import numpy as np, io, scipy.io
>>> data = to_mat_bytes({"K": np.eye(2), "dofs": np.array(["a.y", "b.y"])})
>>> scipy.io.loadmat(io.BytesIO(data))["K"].tolist()
[[1.0, 0.0], [0.0, 1.0]]
>>> to_mat_bytes({"K": np.eye(2)}) == to_mat_bytes({"K": np.eye(2)})
True
"""

from __future__ import annotations

import io
import zipfile
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["to_mat_bytes", "to_npz_bytes", "MAT_HEADER"]

#: The descriptive text of the 128-byte MAT-file header (116 bytes, space padded).
MAT_HEADER = b"MATLAB 5.0 MAT-file, written by EXPRESS (express export)"
_FIXED_DATE = (1980, 1, 1, 0, 0, 0)


def to_mat_bytes(matrices: Mapping[str, Any]) -> bytes:
    """A MATLAB 5 ``.mat`` file of ``matrices`` (name -> array), readable by
    ``scipy.io.loadmat``, MATLAB and GNU Octave; string arrays become char matrices."""
    from scipy.io import savemat

    buffer = io.BytesIO()
    savemat(buffer, {name: np.asarray(value) for name, value in matrices.items()}, oned_as="column")
    data = bytearray(buffer.getvalue())
    data[:116] = MAT_HEADER.ljust(116, b" ")
    return bytes(data)


def to_npz_bytes(matrices: Mapping[str, Any]) -> bytes:
    """A NumPy ``.npz`` archive of ``matrices`` (name -> array), readable by
    ``numpy.load`` (no pickles: string arrays are stored as fixed-width unicode)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_STORED) as archive:
        for name, value in matrices.items():
            array = np.asarray(value)
            if array.dtype == object:
                raise TypeError(f"{name}: object arrays are not exported")
            member = io.BytesIO()
            np.lib.format.write_array(member, array, allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=_FIXED_DATE)
            info.external_attr = 0o644 << 16
            archive.writestr(info, member.getvalue())
    return buffer.getvalue()
