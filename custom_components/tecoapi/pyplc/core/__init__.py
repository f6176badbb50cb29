"""The neutral core: what every source and every caller share."""
