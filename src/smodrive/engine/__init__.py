"""The engine layer: the C library's binding (:mod:`smodrive.engine._ffi`), the C structs
of a scenario (:mod:`smodrive.engine.marshal`), the run in chunks (:mod:`smodrive.engine.run`), its
result (:mod:`smodrive.engine.result`), its files (:mod:`smodrive.engine.export`) and direct access to
the plant (:mod:`smodrive.engine.plant`). It imports :mod:`smodrive.model` and
:mod:`smodrive.design` (the LCL observers' tables), nothing above.
"""

from .channels import (
                       CHANNEL_INFO,
                       CHANNELS,
                       CURRENT,
                       FAULT_BITS,
                       LATCHED_FAULTS,
                       LAWS,
                       PHASES,
                       POSITION,
                       START,
                       WARNING_FAULTS,
                       fault_names,
)
from .marshal import (
                       TABLE_RPM,
                       design_over_table,
                       drive_config,
                       lcl_observer_tables,
                       observer_tables,
                       plant_config,
                       profiles,
)
from .result import NO_FAULT, FaultReport, Result
from .run import (
                       DEFAULT_LOG_BUDGET,
                       Engine,
                       LogPlan,
                       SimulationError,
                       controller_fields,
                       log_plan,
                       plant_fields,
                       simulate,
)

__all__ = ["CHANNELS", "CHANNEL_INFO", "CURRENT", "POSITION", "START", "LAWS", "PHASES",
           "FAULT_BITS", "LATCHED_FAULTS", "WARNING_FAULTS", "fault_names", "TABLE_RPM",
           "design_over_table", "drive_config", "plant_config", "profiles", "observer_tables",
           "lcl_observer_tables",
           "NO_FAULT", "FaultReport", "Result", "DEFAULT_LOG_BUDGET", "Engine", "LogPlan",
           "SimulationError", "controller_fields", "log_plan", "plant_fields", "simulate"]
