"""The brute-force references' switches (tests/test_dead_time_clamp.py,
tests/test_lcl_clamp.py): a carrier period cut at every commanded instant,
each leg's switch state on each piece."""

from __future__ import annotations


def switch_pieces(d, T: float, td: float, off: bool = False):
    """(t0, t1, up, low) for each piece of a period of duties `d`: the leg's
    upper switch on ([r + t_dead, f)), its lower one on (before r, from
    f + t_dead), neither (the dead times; every piece with `off`);
    r = (1 - d) T / 2, f = (1 + d) T / 2 (regular sampling at the peak)."""
    r = [(1 - dx) * T / 2 for dx in d]
    f = [(1 + dx) * T / 2 for dx in d]
    marks = {0.0, T}
    for x in range(3):
        marks |= {r[x], r[x] + td, f[x], f[x] + td}
    marks = sorted(m for m in marks if 0.0 <= m <= T)
    for t0, t1 in zip(marks[:-1], marks[1:]):
        tm = 0.5 * (t0 + t1)
        up = [r[x] + td <= tm < f[x] and not off for x in range(3)]
        low = [(tm < r[x] or tm >= f[x] + td) and not off for x in range(3)]
        yield t0, t1, up, low
