"""Tests of xnavlab.robust, one test module per module of the package."""
