"""The model layer: typed, validated parameters (frozen dataclasses) and the
controller values derived from the motor. Pure functions of parameters: it
imports nothing of smodrive above :mod:`smodrive._util`.

Floors, bottom up: :mod:`smodrive.model.fields` (units, ParameterError, field kinds,
Profile) -> :mod:`smodrive.model.pars` (motor, filter, inverter, ADC, load, controller)
-> :mod:`smodrive.model.derive` (controller values from the motor) -> :mod:`smodrive.model.scenario`
(Scenario).
"""

from .fields import LCL_TABLE_RPM, RPM, ParameterError, Profile
from .pars import (
                   B_REL,
                   CURRENT_CONTROL,
                   MOTOR_REQUIRED,
                   POSITION_SOURCES,
                   STARTS,
                   TABLE1_MOTOR,
                   YANG2018_MODES,
                   AdcCfg,
                   ControllerCfg,
                   InverterCfg,
                   LclFilterPars,
                   LoadCfg,
                   MotorPars,
                   yang2018_mode,
)
from .scenario import Scenario

__all__ = ["RPM", "LCL_TABLE_RPM", "ParameterError", "Profile", "TABLE1_MOTOR",
           "MOTOR_REQUIRED", "B_REL", "CURRENT_CONTROL", "POSITION_SOURCES", "STARTS",
           "YANG2018_MODES", "yang2018_mode", "MotorPars", "LclFilterPars", "InverterCfg",
           "AdcCfg", "ControllerCfg", "LoadCfg", "Scenario"]
