"""Tests of xnavlab.line, one test module per module of the package."""
