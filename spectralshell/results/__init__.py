"""Stage 5: immutable results with provenance, and their JSON/CSV/NPZ forms."""
