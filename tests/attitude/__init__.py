"""Tests of xnavlab.attitude, one test module per module of the package."""
