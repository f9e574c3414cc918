"""tune (see the package above)."""
