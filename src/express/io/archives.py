"""The binary result files: NumPy ``.npz`` archives and MATLAB ``.mat`` files, as bytes.

Both are deterministic (fixed dates in the archive, a fixed header text in place of the
creation date) and refuse a nan or inf (:func:`express.io.finite.require_finite`); the
bytes are written whole or not at all by :mod:`express.io.output`.
"""

from __future__ import annotations

import io
import zipfile
from collections.abc import Mapping
from typing import Any

from express.io.finite import require_finite

__all__ = ["MAT_HEADER", "mat_bytes", "npz_bytes"]

MAT_HEADER = b"MATLAB 5.0 MAT-file, written by EXPRESS (express export)"
_FIXED_DATE = (1980, 1, 1, 0, 0, 0)
_ZIP64_FROM = int(zipfile.ZIP64_LIMIT / 1.05) - 4096  # ZIP64 sizes from here (zipfile's rule for a known size)


def npz_bytes(arrays: Mapping[str, Any], *, compress: bool = False) -> bytes:
    """A NumPy ``.npz`` archive of ``arrays`` (name -> array), byte-identical run to run
    (fixed zip dates), readable by ``numpy.load`` without pickles; ``compress`` deflates
    the members (zlib level 1); a nan or inf is refused
    (:func:`express.io.finite.require_finite`)."""
    import numpy as np

    buffer = io.BytesIO()
    method = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
    with zipfile.ZipFile(buffer, "w", compression=method) as archive:
        for name, value in arrays.items():
            array = np.asarray(value)
            require_finite(name, array)
            if array.dtype == object:
                raise TypeError(f"{name}: object arrays are not exported")
            info = zipfile.ZipInfo(f"{name}.npy", date_time=_FIXED_DATE)
            info.external_attr = 0o644 << 16
            info.compress_type = method
            if compress:  # floats deflate as well at level 1 as at 6, in less time (ZipInfo.compress_level from 3.13)
                info._compresslevel = 1  # type: ignore[attr-defined]
            with archive.open(info, "w", force_zip64=array.nbytes > _ZIP64_FROM) as member:  # streamed: no copy
                np.lib.format.write_array(member, array, allow_pickle=False)
    return buffer.getvalue()


def mat_bytes(arrays: Mapping[str, Any], *, compress: bool = False) -> bytes:
    """A MATLAB 5 ``.mat`` file of ``arrays`` (vectors as columns), byte-identical run
    to run (the creation date in the header is replaced by :data:`MAT_HEADER`); a nan
    or inf is refused (:func:`express.io.finite.require_finite`)."""
    import numpy as np
    from scipy.io import savemat

    for name, value in arrays.items():
        require_finite(name, value)
    buffer = io.BytesIO()
    savemat(buffer, {name: np.asarray(value) for name, value in arrays.items()}, oned_as="column",
            do_compression=compress)
    data = bytearray(buffer.getvalue())
    data[:116] = MAT_HEADER.ljust(116, b" ")
    return bytes(data)
