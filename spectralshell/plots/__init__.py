"""Stage 7: figures (matplotlib only here, imported lazily by the callers)."""
