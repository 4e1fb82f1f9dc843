"""Tests of xnavlab.mars.kernel, one test module per module of the subpackage."""
