"""smodrive: sliding-mode observer based control of PMSM drives, the
real-time core in C99 and a simulator that runs exactly that code.

The public API, by layer (docs/architecture.md):

- parameters (:mod:`smodrive.model`): :class:`Scenario` and its sections,
  :class:`Profile`, :data:`RPM`, :class:`ParameterError`;
- a run (:mod:`smodrive.engine`): :func:`simulate`, :class:`Result`,
  :data:`CHANNELS`, :func:`fault_names`, :class:`SimulationError`;
- scenario files (:mod:`smodrive.scenario_io`): :func:`load_scenario`,
  :func:`scenario_from_dict`, :func:`scenario_to_toml`, and the papers'
  named scenarios (:func:`catalogue`).

Example
-------
>>> import smodrive as smd
>>> s = smd.Scenario(duration=0.01, w_M0=300 * smd.RPM)
>>> smd.simulate(s).status
0
"""

from .engine import CHANNELS, FAULT_BITS, Result, SimulationError, fault_names, simulate
from .model import (RPM, AdcCfg, ControllerCfg, InverterCfg, LclFilterPars, LoadCfg, MotorPars,
                    ParameterError, Profile, Scenario)
from .scenario_io import load_scenario, scenario_from_dict, scenario_to_toml
from .scenarios import catalogue

__all__ = ["Scenario", "MotorPars", "LclFilterPars", "InverterCfg", "AdcCfg", "ControllerCfg",
           "LoadCfg", "Profile", "RPM", "ParameterError", "simulate", "Result", "CHANNELS",
           "FAULT_BITS", "fault_names", "SimulationError", "load_scenario", "scenario_from_dict",
           "scenario_to_toml", "catalogue"]
