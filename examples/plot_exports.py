"""
Exports: MATLAB, CSV, Parquet, pandas
=====================================

``smodrive run SCENARIO --format npz,mat,csv,parquet`` writes the log in
each format with the unit and description of every channel; from Python the
same is :func:`smodrive.engine.export.write`, and :meth:`Result.to_dataframe`
gives a pandas DataFrame (units in ``df.attrs``).
"""

import tempfile
from pathlib import Path

import scipy.io

from smodrive.engine import export
from smodrive.scenarios import drive
from smodrive.engine import CHANNEL_INFO, simulate

r = simulate(drive.pi_encoder().replace(duration=0.05))

# %%
# Every channel has a unit and a description.
for name in ("t", "w_M", "i_q", "T_e", "u_alpha", "status"):
    unit, what = CHANNEL_INFO[name]
    print(f"{name:8s} [{unit or '-':5s}] {what}")

# %%
# The files, and the MATLAB file read back: one column vector per channel
# and the structs ``units``, ``descriptions``, ``info``.
out = Path(tempfile.mkdtemp())
for p in export.write(r, out, ("npz", "mat", "csv", "parquet")):
    print(p.name, p.stat().st_size, "bytes")
m = scipy.io.loadmat(out / "signals.mat", squeeze_me=True, struct_as_record=False)
print("w_M in MATLAB:", m["w_M"].shape, m["units"].w_M)

# %%
# pandas.
df = r.to_dataframe()
print(df[["t", "w_M", "i_d", "i_q"]].describe().loc[["mean", "std"]])
print(df.attrs["units"]["i_q"])
