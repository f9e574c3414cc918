"""measure (see the package above)."""
