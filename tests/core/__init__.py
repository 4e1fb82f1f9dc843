"""Tests of xnavlab.core, one test module per module of the package."""
