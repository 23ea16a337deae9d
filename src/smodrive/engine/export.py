"""Export a run's log with its units: NumPy (.npz), MATLAB (.mat), CSV and
Parquet.

Every format holds one column per channel of :data:`smodrive.engine.CHANNELS`
(SI units, float64) and says what each is:

``npz``
    ``signals.npz``: one array per channel (``np.load``), and the arrays
    ``_units`` and ``_descriptions`` (strings, in channel order).
``mat``
    ``signals.mat`` (``scipy.io.savemat``, MATLAB 5 format): one column
    vector per channel, the structs ``units`` and ``descriptions`` (a field
    per channel, e.g. ``units.w_M`` is ``'rad/s'``) and ``info`` (scenario
    name, log stride, control period, samples simulated).
``csv``
    ``signals.csv``: a header row of channel names, then one row per
    logged sample (17 significant digits: every float64 reads back exactly,
    with pandas 3's ``read_csv``, or pandas 2's with
    ``float_precision="round_trip"``);
    the units and descriptions in the sidecar ``signals.csv.json``.
``parquet``
    ``signals.parquet`` (pyarrow): the unit and description of each column in
    its field metadata (``unit``, ``description``), the run's information in
    the schema metadata (``smodrive``, JSON).

An empty unit means a dimensionless code (``phase``, ``status``, ``fault``).

Every file is written atomically (:func:`atomic_path`): under a temporary
name in the same folder, then renamed onto its name, so that a run killed
while writing never leaves a truncated file under the final name (an earlier
file of that name stays whole until the new one replaces it).

>>> parse_formats("npz, mat")
('npz', 'mat')
>>> parse_formats("xls")
Traceback (most recent call last):
...
smodrive.model.ParameterError: --format: unknown format 'xls'; the formats are npz, mat, csv, parquet (comma-separated, e.g. npz,mat)
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import zipfile
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np
from scipy.io import savemat

from ..model import ParameterError
from .channels import CHANNEL_INFO, CHANNELS

#: the export formats, by name: the file each writes
FORMATS: dict[str, str] = {"npz": "signals.npz", "mat": "signals.mat", "csv": "signals.csv",
                           "parquet": "signals.parquet"}

Progress = Callable[[float], None]


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary name beside `path` to write the file to: when the block
    ends normally the file is renamed onto `path` (``os.replace``, atomic
    within a folder), when it raises the temporary file is removed and
    `path` is left as it was. The temporary name is hidden
    (``.NAME.RANDOM.tmp``); a process killed in the block may leave it, never
    a partial `path`.

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> with atomic_path(d / "a.txt") as tmp:
    ...     _ = tmp.write_text("whole")
    ...     (d / "a.txt").exists()
    False
    >>> (d / "a.txt").read_text(), sorted(p.name for p in d.iterdir())
    ('whole', ['a.txt'])
    """
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_text(path: str | Path, text: str) -> Path:
    """`text` written to `path` (UTF-8) atomically (:func:`atomic_path`)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def parse_formats(text: str) -> tuple[str, ...]:
    """The formats of a ``--format`` value (comma-separated names of
    :data:`FORMATS`, each once); an unknown one is a ParameterError naming
    it and the valid choices."""
    names = [p.strip().lower() for p in str(text).split(",")]
    bad = [n for n in names if n not in FORMATS]
    if bad or not names:
        what = (f"unknown format{'s' if len(bad) > 1 else ''} {', '.join(map(repr, bad))}"
                if bad else "no format")
        raise ParameterError(f"--format: {what}; the formats are {', '.join(FORMATS)} "
                             "(comma-separated, e.g. npz,mat)")
    return tuple(dict.fromkeys(names))


def channel_table() -> list[dict[str, str]]:
    """Every logged channel: name, unit and description, in log order."""
    return [{"name": c, "unit": CHANNEL_INFO[c][0], "description": CHANNEL_INFO[c][1]}
            for c in CHANNELS]


def run_info(r) -> dict[str, Any]:
    """What a file says about its run: scenario name, log stride (control
    samples per row), control period T_sp (s) and samples simulated."""
    return {"scenario": r.scenario.name, "log_stride": int(r.log_stride),
            "T_sp": float(r.scenario.T_sp), "samples": int(r.samples)}


def write(r, out: Path, formats: tuple[str, ...] = ("npz",),
          progress: Progress | None = None) -> list[Path]:
    """Write the log of `r` (:class:`smodrive.engine.Result`) into the
    folder `out` in each of `formats`; returns the paths written (a
    sidecar included). `progress(fraction)` as the files are written."""
    out = Path(out)
    paths: list[Path] = []
    for k, fmt in enumerate(formats):
        def part(f: float, k=k) -> None:
            if progress is not None:
                progress((k + f) / len(formats))

        writer = {"npz": write_npz, "mat": write_mat, "csv": write_csv,
                  "parquet": write_parquet}[fmt]
        paths += writer(r, out / FORMATS[fmt], part)
    return paths


def write_npz(r, path: Path, progress: Progress | None = None) -> list[Path]:
    """signals.npz (one array per channel, compressed, as
    np.savez_compressed writes it, plus ``_units`` and ``_descriptions``), a
    channel at a time: no copy of the log is made."""
    table = channel_table()
    extra = {"_units": np.array([c["unit"] for c in table]),
             "_descriptions": np.array([c["description"] for c in table])}
    with atomic_path(path) as tmp, zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED,
                                                   allowZip64=True) as zf:
        for k, c in enumerate(CHANNELS):
            with zf.open(f"{c}.npy", "w", force_zip64=True) as f:
                np.lib.format.write_array(f, r[c], allow_pickle=False)
            if progress is not None:
                progress((k + 1) / len(CHANNELS))
        for name, arr in extra.items():
            with zf.open(f"{name}.npy", "w") as f:
                np.lib.format.write_array(f, arr, allow_pickle=False)
    return [Path(path)]


def write_mat(r, path: Path, progress: Progress | None = None) -> list[Path]:
    """signals.mat: a column vector per channel and the structs ``units``,
    ``descriptions`` and ``info``."""
    table = channel_table()
    data: dict[str, Any] = {c["name"]: np.ascontiguousarray(r[c["name"]]).reshape(-1, 1)
                            for c in table}
    data["units"] = {c["name"]: c["unit"] for c in table}
    data["descriptions"] = {c["name"]: c["description"] for c in table}
    data["info"] = run_info(r)
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        savemat(f, data, do_compression=True, oned_as="column")
    if progress is not None:
        progress(1.0)
    return [Path(path)]


def write_csv(r, path: Path, progress: Progress | None = None,
              chunk_rows: int = 20_000) -> list[Path]:
    """signals.csv (a header of channel names, 17 significant digits) and
    its sidecar signals.csv.json (units, descriptions, run information),
    `chunk_rows` rows at a time."""
    path = Path(path)
    n = r.data.shape[0]
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as f:
        f.write(",".join(CHANNELS) + "\n")
        for i in range(0, n, chunk_rows):
            np.savetxt(f, r.data[i:i + chunk_rows], fmt="%.17g", delimiter=",")
            if progress is not None:
                progress(min(1.0, (i + chunk_rows) / max(n, 1)))
    side = write_text(path.with_name(path.name + ".json"), json.dumps(
        {"file": path.name, **run_info(r), "columns": channel_table()}, indent=2,
        ensure_ascii=False) + "\n")
    return [path, side]


def write_parquet(r, path: Path, progress: Progress | None = None) -> list[Path]:
    """signals.parquet: a float64 column per channel with ``unit`` and
    ``description`` in its field metadata; the run's information (JSON) in
    the schema metadata under ``smodrive``."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise ParameterError("--format parquet needs pyarrow: pip install pyarrow") from None
    table = channel_table()
    fields = [pa.field(c["name"], pa.float64(), metadata={"unit": c["unit"],
                                                          "description": c["description"]})
              for c in table]
    schema = pa.schema(fields, metadata={"smodrive": json.dumps(run_info(r))})
    arrays = [pa.array(np.ascontiguousarray(r[c["name"]])) for c in table]
    with atomic_path(path) as tmp:
        pq.write_table(pa.Table.from_arrays(arrays, schema=schema), str(tmp))
    if progress is not None:
        progress(1.0)
    return [Path(path)]


def to_dataframe(r):
    """The log of `r` as a pandas DataFrame: a float64 column per channel
    (``t`` included), the units and descriptions by channel in
    ``df.attrs["units"]`` and ``df.attrs["descriptions"]``, the run's
    information in ``df.attrs["run"]``."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("Result.to_dataframe() needs pandas: pip install pandas "
                          "(or the extra: pip install 'smodrive[pandas]')") from None
    df = pd.DataFrame(r.data, columns=list(CHANNELS), copy=True)
    table = channel_table()
    df.attrs["units"] = {c["name"]: c["unit"] for c in table}
    df.attrs["descriptions"] = {c["name"]: c["description"] for c in table}
    df.attrs["run"] = run_info(r)
    return df
