"""The per-speed fields of yao2022's offline observer design, in order: the
one list the design's types and every copy of its layout are built from.

:class:`smodrive.design.yao2022.ObserverMatrices` (one speed) and
:class:`~smodrive.design.yao2022.DesignTables` (speed first) take their
fields from it, ``yao2022.MATRIX_FIELDS`` is its names,
:data:`smodrive.design.cheader.REALTIME_FIELDS` the real-time ones; the core's
table models (``smd_lcl_model``, ``smd_linobs_model``) name the field each of
their arrays holds in the header (``@design(...)``), and the binding packs the
tables by those names, checked against the shapes here at import
(``smodrive.engine.marshal``)."""

from __future__ import annotations

#: (name, shape at one speed, kind "f" real or "i" integer, real-time: a
#: firmware needs it) in declaration order; the meanings are in
#: ObserverMatrices' docstring
OBSERVER_FIELDS: tuple[tuple[str, tuple[int, ...], str, bool], ...] = (
    ("G", (6, 6), "f", True),
    ("H", (6, 2), "f", True),
    ("F", (6, 2), "f", True),
    ("T_r", (6, 6), "f", True),
    ("B", (2, 2), "f", True),
    ("H_c", (2, 2), "f", True),
    ("D1", (2, 2), "f", True),
    ("D2", (2, 2), "f", True),
    ("Gamma_c", (2, 2), "f", True),
    ("Gamma_1", (2, 2), "f", True),
    ("Gamma_2", (2, 2), "f", True),
    ("G_s", (2, 2), "f", True),
    ("G_c", (2, 2), "f", False),
    ("G_u", (2, 2), "f", False),
    ("G_y", (2, 2), "f", False),
    ("G_sm", (6, 6), "f", False),
    ("L", (2, 2), "f", False),
    ("K_c", (2, 2), "f", True),
    ("K_y", (2, 2), "f", True),
    ("k", (), "f", True),
    ("a1_2", (), "f", True),
    ("a2_2", (), "f", True),
    ("a1_3", (), "f", True),
    ("a2_3", (), "f", True),
    ("N_2", (), "i", True),
    ("N_3", (), "i", True),
    ("L_s", (4, 4), "f", True),
    ("Theta", (4, 4), "f", True),
    ("Theta_y", (4, 4), "f", True),
    ("Theta_u", (4, 2), "f", True),
)
