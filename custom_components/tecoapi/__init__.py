"""The Tecomat TecoApi integration."""
