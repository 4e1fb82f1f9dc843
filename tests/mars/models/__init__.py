"""Tests of xnavlab.mars.models, one test module per module of the subpackage."""
