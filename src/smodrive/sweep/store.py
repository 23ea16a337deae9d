"""A sweep's results folder OUT: ``OUT/runs/part-*.parquet`` (one row a
run, one part a finished batch, each written whole or not at all),
``OUT/sweep.json`` (the sweep as it ran, with its base scenario in full)
and ``OUT/sweep.toml`` (the file given); reading them back."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from ..engine.export import write_text
from ..model import ParameterError
from .plan import expand
from .spec import SweepSpec, parse_sweep

# pyarrow is imported where a function reads or writes Parquet: an optional
# dependency elsewhere (`smodrive run --format parquet` says how to install
# it), so the CLI, which imports this package, starts without it


def schema(spec: SweepSpec):
    """The columns of a row of `spec` (a pyarrow Schema): run id and index,
    the axes (and the seed), the metrics, the standard columns (status,
    fault, wall time, ..., and the operating point: held, not_held and the
    shares of the window it was judged by)."""
    import pyarrow as pa  # optional: see above

    cols = [("run_id", pa.string()), ("index", pa.int64())]
    for a in spec.axes:
        typ = (pa.int64() if a.integer else pa.float64() if a.numeric
               else pa.bool_() if all(isinstance(v, bool) for v in a.values) else pa.string())
        cols.append((a.name, typ))
    if spec.seeds:
        cols.append(("seed", pa.int64()))
    cols += [(m, pa.float64()) for m in spec.metrics]
    cols += [("status", pa.string()), ("error", pa.string()), ("first_fault", pa.string()),
             ("fault_t", pa.float64()), ("final_fault", pa.string()), ("wall_s", pa.float64()),
             ("steps", pa.int64()), ("smodrive_version", pa.string()), ("held", pa.bool_()),
             ("not_held", pa.string()), ("speed_offset_rpm", pa.float64()),
             ("i_limit_share", pa.float64()), ("u_limit_share", pa.float64())]
    return pa.schema(cols)


def runs_dir(out: Path) -> Path:
    return Path(out) / "runs"


def _part_files(out: Path) -> list[Path]:
    d = runs_dir(out)
    return sorted(d.glob("part-*.parquet")) if d.is_dir() else []


def done_ids(out: Path) -> set[str]:
    """The run ids OUT has a row for."""
    import pyarrow.parquet as pq  # optional: see above

    ids: set[str] = set()
    for p in _part_files(out):
        ids.update(pq.read_table(p, columns=["run_id"]).column(0).to_pylist())
    return ids


def read_parts(out: Path):
    """Every row of OUT/runs (all parts, as written: a run twice would show
    twice), as one pyarrow Table."""
    import pyarrow as pa  # optional: see above
    import pyarrow.parquet as pq

    tables = [pq.read_table(p) for p in _part_files(out)]
    if not tables:
        return None
    return pa.concat_tables(tables, promote_options="permissive")


def load_results(spec: SweepSpec, out: Path) -> dict[str, np.ndarray]:
    """The rows of OUT that belong to the runs of `spec` (one per run, in
    run order), as columns: name -> numpy array."""
    import pyarrow as pa  # optional: see above

    t = read_parts(out)
    runs = expand(spec)
    order = {r.id: r.index for r in runs}
    if t is None:
        return {c: np.array([]) for c in schema(spec).names}
    ids = t.column("run_id").to_pylist()
    keep, seen = [], set()
    for i, rid in enumerate(ids):
        if rid in order and rid not in seen:
            seen.add(rid)
            keep.append(i)
    keep.sort(key=lambda i: order[ids[i]])
    t = t.take(keep)
    cols = {}
    for name in t.column_names:
        col = t.column(name)
        cols[name] = np.array(col.to_pylist(), dtype=object if col.type == pa.string() else None)
    return cols


def write_part(out: Path, spec: SweepSpec, rows: list[dict]) -> Path:
    """`rows` (a finished batch) as one part of OUT/runs."""
    import pyarrow as pa  # optional: see above
    import pyarrow.parquet as pq

    tag = hashlib.sha256("".join(r["run_id"] for r in rows).encode()).hexdigest()[:12]
    path = runs_dir(out) / f"part-{min(r['index'] for r in rows):08d}-{tag}.parquet"
    tmp = path.with_name("." + path.name + f".{os.getpid()}.tmp")
    sch = schema(spec)
    table = pa.Table.from_pylist([{k: r.get(k) for k in sch.names} for r in rows], schema=sch)
    pq.write_table(table, tmp)
    with open(tmp, "rb") as f:
        os.fsync(f.fileno())
    os.replace(tmp, path)  # a part is there whole or not at all
    return path


def clear_partial(out: Path) -> None:
    """Remove the parts a killed sweep left half written (never read)."""
    for tmp in runs_dir(out).glob(".part-*.tmp"):
        tmp.unlink()


def prepare_out(spec: SweepSpec, out: Path, sweep_text: str | None = None) -> None:
    """OUT/runs made; OUT/sweep.json (and OUT/sweep.toml, the file given)
    written, atomically: a killed sweep never leaves half a sweep.json."""
    out = Path(out)
    runs_dir(out).mkdir(parents=True, exist_ok=True)
    write_text(out / "sweep.json", json.dumps(
        {"name": spec.name, "spec": spec.raw}, indent=1, default=repr) + "\n")
    if sweep_text is not None:
        write_text(out / "sweep.toml", sweep_text)


def load_out_spec(out: Path) -> SweepSpec:
    """The sweep whose results OUT holds (OUT/sweep.json)."""
    p = Path(out) / "sweep.json"
    if not p.is_file():
        raise ParameterError(f"{out}: no sweep.json there (not the --out of a sweep)")
    d = json.loads(p.read_text(encoding="utf-8"))
    return parse_sweep(d["spec"], d.get("name", "sweep"))
