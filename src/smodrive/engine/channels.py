"""The names of the engine's codes and logged channels: composition codes,
start-up phases, every logged channel with its unit and meaning, and the
bits of the controller's fault word (core/include/smodrive/smd_drive.h)."""

from __future__ import annotations

from . import _codes

#: the composition codes by the scenario's names (generated from the C enums)
CURRENT, POSITION, START, LAWS = _codes.CURRENT, _codes.POSITION, _codes.START, _codes.LAWS
PHASES = {0: "forced (I/f)", 1: "encoder (handover)", 2: "position source"}

#: every logged channel, in row order (enum smd_log_channel, smd_engine.h)
CHANNELS: tuple[str, ...] = tuple(name for name, _, _ in _codes.LOG_CHANNELS)
#: every logged channel: unit and meaning (the enum's @log annotations)
CHANNEL_INFO: dict[str, tuple[str, str]] = {
    name: (unit, meaning) for name, unit, meaning in _codes.LOG_CHANNELS}


#: bits of the controller's fault word (generated from core/include/smodrive/smd_drive.h)
FAULT_BITS = _codes.FAULT_BITS
#: the latched ones: the drive stays in its safe state until cleared (generated)
LATCHED_FAULTS = _codes.LATCHED_FAULTS
#: warnings: reported while their condition holds, the drive runs on (generated)
WARNING_FAULTS = _codes.WARNING_FAULTS


def fault_names(word: int) -> list[str]:
    """The names of the bits set in a fault word."""
    return [k for k, b in FAULT_BITS.items() if int(word) & b]

