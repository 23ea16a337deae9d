"""Instructions per call of the real-time parts (yao2022 Table VI), counted
with valgrind's callgrind on the host build of the C core (x86-64, -O2,
float). Needs the source tree, a C compiler and valgrind."""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

N_CALLS = 1000  # benchmarks/cost/obs_cost.c
PARTS = {"prediction": "cost_prediction", "reaching_law": "cost_reach", "pll": "cost_pll"}


def source_root() -> Path | None:
    here = Path(__file__).resolve()
    for parent in here.parents:
        if (parent / "core" / "src").is_dir() and (parent / "benchmarks" / "cost").is_dir():
            return parent
    return None


def instructions_per_call() -> dict[str, float]:
    """{part: instructions per call}; raises RuntimeError with the reason if a
    tool or the source tree is missing."""
    root = source_root()
    if root is None:
        raise RuntimeError("the C sources are not available (run from the source tree)")
    for tool in ("cc", "valgrind", "callgrind_annotate"):
        if shutil.which(tool) is None:
            raise RuntimeError(f"{tool} is not installed")
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "obs_cost"
        srcs = sorted(str(p) for p in (root / "core" / "src").glob("*.c"))
        subprocess.run(["cc", "-std=c99", "-O2", "-g", "-I", str(root / "core" / "include"),
                        str(root / "benchmarks" / "cost" / "obs_cost.c"), *srcs, "-lm", "-o",
                        str(exe)], check=True, capture_output=True)
        out = Path(tmp) / "callgrind.out"
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        str(exe)], check=True, capture_output=True)
        ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], check=True,
                             capture_output=True, text=True).stdout
    res = {}
    for part, fn in PARTS.items():
        m = re.search(r"^\s*([\d,]+)\s+\([^)]*\)\s+\S*:" + fn + r"\b", ann, re.M) or re.search(
            r"^\s*([\d,]+)\s+.*\b" + fn + r"\b", ann, re.M)
        if not m:
            raise RuntimeError(f"callgrind output has no entry for {fn}")
        res[part] = int(m.group(1).replace(",", "")) / N_CALLS
    return res
