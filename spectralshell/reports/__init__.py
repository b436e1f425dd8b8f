"""Stage 6b: the figure registry (name -> thesis reproduction) and reports."""
