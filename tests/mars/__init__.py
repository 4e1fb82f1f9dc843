"""Tests of xnavlab.mars, one test module per module of the package."""
