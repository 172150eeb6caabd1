"""A scene's matrix files, checked before they are read: a file name the system refuses, a
truncated or corrupt archive, and a header that declares more than ``MAX_MATRIX_BYTES`` are
named by their key instead of reaching the readers (which would allocate what the header says)."""

from __future__ import annotations

import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from ..structure import load_matrix

#: The largest matrix a scene's file may declare (bytes of its values once read): 2 GiB.  A larger
#: model is read in a script with ``hbm.structure.load_matrix`` (which has no bound), or with this
#: constant raised.
MAX_MATRIX_BYTES = 2 << 30
#: Header lines of a Matrix Market file read for its declared size (comments included).
_MTX_HEADER_LINES = 10_000


def read_matrix(value: Any, key: str) -> Any:
    """``load_matrix(value, name=key)`` after the checks of the module docstring; ValueError naming
    ``key``, the file and the problem."""
    text = str(value)
    file = Path(text.split(".npz:", 1)[0] + ".npz" if ".npz:" in text else text)
    got = f"got {key}={text if len(text) <= 200 else text[:200] + '...'!r}"
    try:
        exists = file.is_file()
    except OSError as exc:  # a name the system refuses (too long, ...)
        raise ValueError(f"{key} must name a matrix file that can be opened, {got} ({len(text)} characters: "
                         f"{exc.strerror or exc})") from None
    if exists:
        declared = _declared_bytes(file, key, got)
        if declared is not None and declared > MAX_MATRIX_BYTES:
            raise ValueError(f"{key}: the file declares a matrix of {declared / 2 ** 30:.3g} GiB, more than a "
                             f"scene reads (hbm.scenes.matrices.MAX_MATRIX_BYTES = {MAX_MATRIX_BYTES / 2 ** 30:g} "
                             f"GiB; read a larger model in a script with hbm.structure.load_matrix), {got}")
    try:
        return load_matrix(value, name=key)
    except (zipfile.BadZipFile, EOFError, MemoryError, OverflowError) as exc:
        raise ValueError(f"{key} must name a matrix file that can be read, {got} ({type(exc).__name__}: "
                         f"{exc})") from None


def _declared_bytes(file: Path, key: str, got: str) -> int | None:
    """The bytes of values the file's header declares (None where it declares none we read)."""
    suffix = file.suffix.lower()
    try:
        if suffix == ".mtx":
            return _mtx_bytes(file, key, got)
        if suffix == ".npy":
            with file.open("rb") as fh:
                declared = _npy_bytes(fh)
                held = file.stat().st_size - fh.tell()
            if declared is not None and declared <= MAX_MATRIX_BYTES and declared > held:
                raise ValueError(f"{key} must name a complete .npy file, {got} (its header declares {declared} bytes "
                                 f"of values, the file holds {held}: truncated)")
            return declared
        if suffix == ".npz":
            if not zipfile.is_zipfile(file):
                raise ValueError(f"{key} must name a .npz file (a zip archive), {got} (not a zip archive, or "
                                 "truncated)")
            with zipfile.ZipFile(file) as z:
                return sum(info.file_size for info in z.infolist())
    except (OSError, zipfile.BadZipFile, UnicodeError) as exc:
        raise ValueError(f"{key} must name a matrix file that can be read, {got} ({type(exc).__name__}: "
                         f"{exc})") from None
    except ValueError as exc:
        if str(exc).startswith(key):
            raise
        return None  # a header the reader refuses itself, by name
    return None


def _npy_bytes(fh) -> int | None:
    fmt = np.lib.format
    version = fmt.read_magic(fh)
    read = fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0
    shape, _, dtype = read(fh)
    return int(np.prod(shape, dtype=object)) * dtype.itemsize


def _mtx_bytes(file: Path, key: str, got: str) -> int | None:
    """From the size line of a Matrix Market file: ``rows cols`` (array: rows cols values) or
    ``rows cols entries`` (coordinate: 16 bytes an entry, its two indices and value)."""
    with file.open("r", encoding="latin-1") as fh:
        first = fh.readline().lower()
        for _ in range(_MTX_HEADER_LINES):
            line = fh.readline()
            if not line:
                return None
            if line.startswith("%") or not line.strip():
                continue
            numbers = [int(v) for v in line.split()[:3]]
            if "coordinate" in first and len(numbers) == 3:
                values = max(numbers[2], 0)
            elif len(numbers) >= 2:
                values = max(numbers[0], 0) * max(numbers[1], 0)
            else:
                return None
            if "coordinate" not in first and "symmetric" not in first and "hermitian" not in first \
                    and 8 * values <= MAX_MATRIX_BYTES and values > file.stat().st_size // 2:
                # every value takes at least two characters (a digit and a separator)
                raise ValueError(f"{key} must name a complete Matrix Market file, {got} (its header declares "
                                 f"{values} values, the file has {file.stat().st_size} bytes: truncated)")
            return 16 * values if "coordinate" in first else 8 * values
    return None
