"""Tests for the TecoApi PLC simulator itself."""
