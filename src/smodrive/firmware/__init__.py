"""The firmware layer: the real-time core on a Cortex-M4F. The vector
runner (core/target) built for the host and for QEMU's ``mps2-an386``
(:mod:`smodrive.firmware.build`), test vectors (:mod:`smodrive.firmware.vectors`), running and comparing the
two builds (:mod:`smodrive.firmware.run`), processor-in-the-loop (:mod:`smodrive.firmware.pil`), cycle counts
from the emulator's trace (:mod:`smodrive.firmware.cycles`) and the C header of a drive's
configuration (:mod:`smodrive.firmware.header`). It imports the engine, the design and the
model; the scenarios it runs are given to it
(:mod:`smodrive.scenarios.target_cases` names the standard ones).
"""

from .build import FAST_DEFINES, FIXED, FMATH_DEFINES, fixed_flags, MATH_DEFINES, MATH_FUNCS, TargetError, build, c_root
from .cycles import (
    BUDGET,
    FLASH,
    TABLE6_PAPER,
    CycleRow,
    Flash,
    cycle_table,
    sizes,
    table6_cycles,
    trace_windows,
)
from .pil import PilResult, pil
from .pil import report as pil_report
from .run import compare, drive_case, record, run_both, run_host, run_m4, ulp_distance
from .vectors import (
                      BlockCase,
                      DriveCase,
                      TablesCase,
                      drive_outputs,
                      read_outputs,
                      variants,
                      write_vectors,
)

__all__ = ["FAST_DEFINES", "FIXED", "fixed_flags", "FMATH_DEFINES", "MATH_DEFINES", "MATH_FUNCS", "TargetError", "build",
           "c_root", "BUDGET", "FLASH", "Flash", "TABLE6_PAPER", "CycleRow", "cycle_table", "sizes", "table6_cycles", "trace_windows",
           "PilResult", "pil", "pil_report", "compare", "drive_case", "record", "run_both", "run_host", "run_m4",
           "ulp_distance", "BlockCase", "DriveCase", "TablesCase", "drive_outputs",
           "read_outputs", "variants", "write_vectors"]
