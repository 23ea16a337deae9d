"""Hand-written methods of the generated ctypes mirrors (their base classes;
tools/gen_layout.py names them in its MIXINS)."""

from __future__ import annotations


class CplxMethods:
    """smd_cplx from and to a Python complex."""

    @classmethod
    def of(cls, z: complex):
        return cls(float(z.real), float(z.imag))

    def __complex__(self) -> complex:
        return complex(self.re, self.im)
