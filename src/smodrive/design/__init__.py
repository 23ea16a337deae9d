"""Offline design maths (parameter-only computations handed to the core as tables)."""
