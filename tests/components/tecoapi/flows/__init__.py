"""Tests of the integration's flows (custom_components/tecoapi/flows/)."""
