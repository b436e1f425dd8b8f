"""Stage 5: immutable results with provenance, and their JSON/CSV/NPZ forms.

Every result derives from :class:`spectralshell.results.base.Result` (``to_dict``, ``summary``,
``save``/``load``, a short repr). :mod:`spectralshell.results.records` holds the record types
that the solvers return and the results store; it is a leaf that any stage may import.
"""
