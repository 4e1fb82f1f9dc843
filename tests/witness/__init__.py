"""Witness tests: our timing numbers against the field's own tools (PINT, stingray), offline."""
