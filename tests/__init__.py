"""Tests for the TecoApi integration, its client library and the PLC simulator."""
