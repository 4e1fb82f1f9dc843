"""Tests of xnavlab.mars.navigation, one test module per module of the subpackage."""
