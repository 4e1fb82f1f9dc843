"""Tests of xnavlab.mars.faults, one test module per module of the subpackage."""
