"""TecoApi: the PLC web server's HTTP JSON API."""
