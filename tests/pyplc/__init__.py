"""Tests for the TecoApi client library (no Home Assistant)."""
