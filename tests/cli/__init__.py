"""Tests of xnavlab.cli, one test module per module of the package."""
