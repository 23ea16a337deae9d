"""A sweep's results folder OUT: ``OUT/runs/part-*.parquet`` (one row a
run, one part a finished batch, each written whole or not at all),
``OUT/sweep.json`` (the sweep as it ran, with its base scenario in full)
and ``OUT/sweep.toml`` (the file given); reading them back; whether a
sweep may run into OUT (its own results, or none)."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..engine.export import write_text
from ..model import ParameterError
from .plan import expand
from .spec import SweepSpec, parse_sweep, run_count

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


def done_rows(out: Path) -> dict[str, tuple[str, bool, str]]:
    """What the rows of OUT say of their runs, by run id: (status, held,
    final_fault), for a sweep's count of the runs it reuses (a run written
    twice: its first row)."""
    import pyarrow.parquet as pq  # optional: see above

    rows: dict[str, tuple[str, bool, str]] = {}
    for p in _part_files(out):
        names = pq.read_schema(p).names
        t = pq.read_table(p, columns=[c for c in ("run_id", "status", "held", "final_fault")
                                      if c in names]).to_pydict()
        n = len(t["run_id"])
        # (a part of row format 1 has no "held"; its run ids are no current sweep's)
        held = t.get("held") or [True] * n
        for rid, status, h, final in zip(t["run_id"], t["status"], held, t["final_fault"]):
            rows.setdefault(rid, (status, bool(h), final))
    return rows


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
    """OUT/runs made; OUT/sweep.json and OUT/sweep.toml (`sweep_text`, by
    default the text of the file `spec` was read from: a built-in sweep's
    too) written, atomically: a killed sweep never leaves half a sweep.json."""
    out = Path(out)
    runs_dir(out).mkdir(parents=True, exist_ok=True)
    write_text(out / "sweep.json", json.dumps(
        {"name": spec.name, "spec": spec.raw}, indent=1, default=repr) + "\n")
    text = sweep_text if sweep_text is not None else spec.text
    if text is not None:
        write_text(out / "sweep.toml", text)


def identity(spec: SweepSpec) -> dict[str, Any]:
    """What makes the runs of `spec` (their ids, values and order), by the
    name a difference is told with: two specs with the same identity have
    the same runs. The title, the plots and the batch size are not part of
    it (a sweep given other maps resumes), nor is sweep.seed where nothing
    is drawn."""
    drawn = spec.sample == "lhs" or any(a.kind == "draw" for a in spec.axes)
    out: dict[str, Any] = {
        "its base scenario": spec.base_toml, "its metrics": tuple(spec.metrics),
        "its window": tuple(spec.window),
        "its sampling": (spec.sample, spec.samples, spec.seed if drawn else None),
        "its axes' order": tuple(spec.axis_names)}
    for a in spec.axes:
        out[f"axis {a.name}"] = (a.keys, a.relative_to, a.scale, a.values, a.kind, a.marginal)
    out["its seeds"] = (spec.seed_key if spec.seeds else None, spec.seeds,
                        sorted(spec.seeds_where.items()))
    return out


def check_out(spec: SweepSpec, out: Path) -> None:
    """Refuse (a ParameterError naming OUT and what differs) to run `spec`
    into a folder that holds the results of another sweep: its rows would
    share OUT/runs with this one's, and this sweep's results and maps would
    leave them out without a word. The same sweep (:func:`identity`)
    resumes there; a folder without results is anyone's."""
    out = Path(out)
    if not _part_files(out):
        return
    fix = (f"choose another --out folder, or delete {out} (the results in it with it) to run "
           "this sweep there")
    try:
        old = load_out_spec(out)
    except (ParameterError, ValueError, KeyError, TypeError, AttributeError, OSError) as exc:
        # (results whose sweep.json is missing or unreadable: whose they are is unknown)
        raise ParameterError(f"sweep {spec.name}: {out} holds results (runs/part-*.parquet) "
                             f"of a sweep that its sweep.json does not tell ({exc}); "
                             f"{fix}") from None
    a, b = identity(old), identity(spec)
    diffs = [k for k in dict.fromkeys([*b, *a]) if a.get(k) != b.get(k)]
    if diffs:
        raise ParameterError(f"sweep {spec.name}: {out} holds the results of another sweep "
                             f"({old.name}: {run_count(old)[1]}); it differs in "
                             f"{', '.join(diffs)}: {fix}")


def load_out_spec(out: Path) -> SweepSpec:
    """The sweep whose results OUT holds (OUT/sweep.json)."""
    p = Path(out) / "sweep.json"
    if not p.is_file():
        raise ParameterError(f"{out}: no sweep.json there (not the --out of a sweep)")
    d = json.loads(p.read_text(encoding="utf-8"))
    return parse_sweep(d["spec"], d.get("name", "sweep"))
