"""PLCComS: Teco's push-capable text protocol over TCP."""
