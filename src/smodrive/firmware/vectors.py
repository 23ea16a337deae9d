"""Test vectors for the vector runner (core/target/smd_vec.h): the cases
(a recorded drive, a block on its PRNG inputs, the LCL observers' tables),
their file, the runner's outputs, and the edge-case variants of a recorded
drive case."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import struct
from pathlib import Path

import numpy as np

from ..engine import _ffi
from .build import (
    BLOCKS,
    CASE_BLOCK,
    CASE_DRIVE,
    CASE_END,
    CASE_TABLES,
    IN_WORDS,
    MAGIC,
    SAMPLE_BYTES,
    VERSION,
    VIEW_BYTES,
    TargetError,
)

# ----------------------------------------------------------------- vectors --

def _config_words(obj: ct.Structure) -> bytes:
    """A config struct as the runner reads it (core/target/smd_cfg_read.h):
    each scalar a 4-byte little-endian word in declaration order, pointers
    skipped."""
    out = bytearray()
    for name, typ in obj._fields_:
        val = getattr(obj, name)
        if typ is ct.c_void_p or (isinstance(typ, type) and issubclass(typ, ct._Pointer)):
            continue
        if isinstance(typ, type) and issubclass(typ, ct.Structure):
            out += _config_words(val)
        elif isinstance(typ, type) and issubclass(typ, ct.Array):
            for x in val:
                out += _config_words(x) if isinstance(x, ct.Structure) else _scalar(typ._type_, x)
        else:
            out += _scalar(typ, val)
    return bytes(out)


def _scalar(typ, val) -> bytes:
    if typ is ct.c_float:
        return struct.pack("<f", val)
    if typ in (ct.c_int, ct.c_int32):
        return struct.pack("<i", val)
    raise TypeError(f"no 4-byte wire form for {typ}")


def _tables_bytes(tables) -> bytes:
    if tables is None:
        return struct.pack("<ii", 0, 0)
    m, lin = np.ascontiguousarray(tables[0], "<f4"), np.ascontiguousarray(tables[1], "<f4")
    return (struct.pack("<i", m.shape[0]) + m.tobytes()
            + struct.pack("<i", lin.shape[0]) + lin.tobytes())


@dataclasses.dataclass
class DriveCase:
    """The whole drive step on a recorded or synthetic input sequence."""
    name: str
    config: _ffi.DriveConfig
    tables: tuple | None
    start: tuple[float, float, float]  # theta0, w0 (electrical), i_q0
    inputs: np.ndarray  # (n, 10) float32, smd_drive_in per sample

    def encode(self) -> bytes:
        x = np.ascontiguousarray(self.inputs, dtype="<f4")
        if x.ndim != 2 or x.shape[1] != IN_WORDS:
            raise ValueError(f"{self.name}: inputs must be (n, {IN_WORDS})")
        return (struct.pack("<i", CASE_DRIVE) + _config_words(self.config)
                + _tables_bytes(self.tables) + struct.pack("<fff", *self.start)
                + struct.pack("<i", x.shape[0]) + x.tobytes())


@dataclasses.dataclass
class BlockCase:
    """One block of the core on the runner's PRNG inputs (core/target/smd_vec.c)."""
    name: str
    block: str
    n: int
    seed: int

    def encode(self) -> bytes:
        return struct.pack("<iiiI", CASE_BLOCK, BLOCKS[self.block], self.n, self.seed)


@dataclasses.dataclass
class TablesCase:
    """The LCL observer tables the later lcl_smo / linobs block cases use."""
    name: str
    tables: tuple

    def encode(self) -> bytes:
        return (struct.pack("<i", CASE_TABLES) + _tables_bytes(self.tables)
                + struct.pack("<ff", self.tables[2], self.tables[3]))


def write_vectors(path: Path, cases) -> None:
    with open(path, "wb") as f:
        f.write(struct.pack("<II", MAGIC, VERSION))
        for c in cases:
            f.write(c.encode())
        f.write(struct.pack("<i", CASE_END))


def read_outputs(path: Path) -> list[tuple[int, bytes]]:
    """(kind, outputs) of each case of a runner's output file."""
    data = Path(path).read_bytes()
    if len(data) < 4 or struct.unpack_from("<I", data)[0] != MAGIC:
        raise TargetError(f"{path}: not an output of the runner")
    pos, out = 4, []
    while True:
        if pos + 4 > len(data):
            raise TargetError(f"{path}: truncated after {len(out)} cases")
        kind = struct.unpack_from("<i", data, pos)[0]
        if kind == CASE_END:
            n, err = struct.unpack_from("<ii", data, pos + 4)
            if err or n != len(out):
                raise TargetError(f"{path}: the runner reported an output error")
            return out
        size = struct.unpack_from("<i", data, pos + 4)[0]
        out.append((kind, data[pos + 8:pos + 8 + size]))
        pos += 8 + size


def drive_outputs(body: bytes) -> dict[str, np.ndarray]:
    """A drive case's outputs: init status, then per sample status, duties
    and the controller's view (smd_drive_view) as named arrays."""
    init = struct.unpack_from("<i", body)[0]
    n = (len(body) - 4) // SAMPLE_BYTES
    dt = np.dtype([("status", "<i4"), ("d_abc", "<f4", 3), ("fault", "<u4"), ("pwm_off", "<i4"),
                   ("view", "V%d" % VIEW_BYTES)])
    rec = np.frombuffer(body, dtype=dt, count=n, offset=4)
    view = np.frombuffer(rec["view"].tobytes(), dtype=np.dtype(
        [(f, "<f4", 2) if t is _ffi.Cplx else
         (f, {ct.c_int: "<i4", ct.c_uint32: "<u4"}.get(t, "<f4"))
         for f, t in _ffi.DriveView._fields_]))
    out = {"init": np.array(init), "status": rec["status"], "d_abc": rec["d_abc"],
           "fault": rec["fault"], "pwm_off": rec["pwm_off"]}
    for f in view.dtype.names:
        out[f] = view[f]
    return out



#: the input columns of smd_drive_in
IN_COLS = ("i_a", "i_b", "i1_a", "i1_b", "theta_enc", "w_enc", "u_dc", "w_ref", "i_d_ref",
           "i_q_ref")


def variants(case: DriveCase) -> list[DriveCase]:
    """Edge cases of a recorded drive case: the same run mirrored (negative
    speed: phases b and c swapped, angles and speeds negated), standstill
    (zero speed, constant inputs), saturation (current and speed references
    far beyond the limits, a quarter of the DC link) and faults (NaN, +-inf
    and 1e30 at single samples of each input, u_dc = 0 for ten samples)."""
    c = {k: i for i, k in enumerate(IN_COLS)}
    x = case.inputs.astype(np.float32)
    th0, w0, iq0 = case.start
    m = x.copy()
    m[:, c["i_b"]] = -x[:, c["i_a"]] - x[:, c["i_b"]]
    m[:, c["i1_b"]] = -x[:, c["i1_a"]] - x[:, c["i1_b"]]
    for col in ("theta_enc", "w_enc", "w_ref", "i_q_ref"):
        m[:, c[col]] = -x[:, c[col]]
    z = np.repeat(x[:1], x.shape[0], axis=0)
    z[:, c["w_enc"]] = z[:, c["w_ref"]] = 0.0
    sat = x.copy()
    sat[:, c["i_q_ref"]] *= 50.0
    sat[:, c["i_d_ref"]] += 30.0
    sat[:, c["w_ref"]] *= 5.0
    sat[:, c["u_dc"]] *= 0.25
    f = x.copy()
    bad = (np.nan, np.inf, 1e30, -np.inf)
    for j, col in enumerate(IN_COLS):
        for q, v in enumerate(bad):
            k = 40 + 11 * (4 * j + q)
            if k < f.shape[0]:
                f[k, c[col]] = v
    f[min(30, f.shape[0] - 1):min(40, f.shape[0]), c["u_dc"]] = 0.0
    return [
        DriveCase(case.name + ".mirrored", case.config, case.tables, (-th0, -w0, -iq0), m),
        DriveCase(case.name + ".standstill", case.config, case.tables, (th0, 0.0, 0.0), z),
        DriveCase(case.name + ".saturated", case.config, case.tables, case.start, sat),
        DriveCase(case.name + ".faults", case.config, case.tables, case.start, f),
    ]


