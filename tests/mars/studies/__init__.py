"""Tests of xnavlab.mars.studies, one test module per module of the subpackage."""
