"""A real Home Assistant with this integration: its configuration, its process, and the browser test.

`scripts/develop` uses the configuration and the REST provisioning to start the live
demo; `tests/e2e/test_browser.py` drives the same Home Assistant in Chromium.
"""
