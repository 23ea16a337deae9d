"""The logged signals of one run (:class:`Result`) and when its controller
reported a fault (:class:`FaultReport`)."""

from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np

from ..model import RPM, Scenario
from .channels import CHANNEL_INFO, CHANNELS, fault_names
from .export import to_dataframe


@dataclass(frozen=True)
class FaultReport:
    """When the controller first reported a fault, with which bits, and the
    fault word of the last sample (non-zero: the run ends in a fault)."""

    t_first: float | None  # s; None: no fault
    first: int
    final: int

    @property
    def ends_in_fault(self) -> bool:
        return self.final != 0

    def as_dict(self) -> dict:
        return {"first_fault_t": self.t_first, "first_fault": fault_names(self.first),
                "final_fault": fault_names(self.final)}


NO_FAULT = FaultReport(None, 0, 0)


@dataclass
class Result:
    """Logged signals of one run, by channel name (:data:`CHANNELS`; units
    and meanings: :data:`CHANNEL_INFO`, :meth:`unit`)."""

    scenario: Scenario
    data: np.ndarray  # rows x channels
    status: int
    faults: FaultReport = NO_FAULT
    log_stride: int | None = None  # control samples per row (None: the scenario's)
    samples: int | None = None  # control samples simulated (None: the scenario's n_steps)

    def __post_init__(self) -> None:
        if self.log_stride is None:
            self.log_stride = self.scenario.log_stride
        if self.samples is None:
            self.samples = self.scenario.n_steps

    def __getitem__(self, name: str) -> np.ndarray:
        """The logged channel `name` (:data:`CHANNELS`); an unknown name is
        a KeyError naming it and the channels."""
        try:
            return self.data[:, CHANNELS.index(name)]
        except ValueError:
            raise Result._no_channel(name) from None

    @staticmethod
    def unit(name: str) -> str:
        """The SI unit of channel `name` ("" for a dimensionless code).

        >>> Result.unit("T_e")
        'N m'
        """
        try:
            return CHANNEL_INFO[name][0]
        except (KeyError, TypeError):
            raise Result._no_channel(name) from None

    @staticmethod
    def description(name: str) -> str:
        """What channel `name` is.

        >>> Result.description("w_M")
        'true mechanical speed'
        """
        try:
            return CHANNEL_INFO[name][1]
        except (KeyError, TypeError):
            raise Result._no_channel(name) from None

    @staticmethod
    def _no_channel(name) -> KeyError:
        """The KeyError for a name that is not a channel: the closest
        channels, a derived quantity's property, and every channel."""
        hint = ""
        if isinstance(name, str) and isinstance(getattr(Result, name, None), property):
            hint = f" ({name} is derived: Result.{name})"
        elif isinstance(name, str):
            close = difflib.get_close_matches(name, CHANNELS, n=3, cutoff=0.6)
            if close:
                hint = f" (closest: {', '.join(close)})"
        return KeyError(f"{name!r} is not a logged channel{hint}; the channels are "
                        f"{', '.join(CHANNELS)} (smodrive.engine.CHANNELS, CHANNEL_INFO)")

    def to_dataframe(self):
        """The log as a pandas DataFrame (needs pandas: the extra
        ``smodrive[pandas]``): a column per channel, units and descriptions
        in ``df.attrs["units"]`` and ``df.attrs["descriptions"]``
        (:func:`smodrive.engine.export.to_dataframe`)."""
        return to_dataframe(self)

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    def window(self, t0: float, t1: float) -> np.ndarray:
        """Boolean mask of samples with t0 <= t < t1."""
        return (self.t >= t0) & (self.t < t1)

    @property
    def theta_error(self) -> np.ndarray:
        """theta_r - theta_hat wrapped to [-pi, pi), rad."""
        d = self["theta_r"] - self["theta_hat"]
        return (d + np.pi) % (2 * np.pi) - np.pi

    @property
    def n_rpm(self) -> np.ndarray:
        """True speed, r/min."""
        return self["w_M"] / RPM

    @property
    def n_hat_rpm(self) -> np.ndarray:
        """Speed the controller uses, r/min (mechanical)."""
        return self["w_hat"] / self.scenario.motor.n_p / RPM


