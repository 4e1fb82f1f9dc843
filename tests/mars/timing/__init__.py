"""Tests of xnavlab.mars.timing, one test module per module of the subpackage."""
