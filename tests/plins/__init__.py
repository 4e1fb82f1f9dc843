"""Tests of xnavlab.plins, one test module per module of the package."""
