"""kit (see the package above)."""
