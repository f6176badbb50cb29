"""Tests of the custom components, one folder each (Home Assistant's layout)."""
