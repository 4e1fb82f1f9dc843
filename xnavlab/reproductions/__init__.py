"""Registered reproductions, one module per chapter or paper.

Every module in this package is imported by :func:`xnavlab.reproduce.ids`; each
registers its IDs with :func:`xnavlab.reproduce.register`.
"""

__all__: list[str] = []
