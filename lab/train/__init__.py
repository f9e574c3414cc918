"""train (see the package above)."""
