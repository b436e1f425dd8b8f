"""Stage 8: the figure registry (name -> thesis reproduction) and reports."""
