"""
A parameter sweep from a scene file
===================================

:func:`spectralshell.sweep` runs the sweep scene ``map.toml`` (a kappa x nu grid for degrees
m = 2..4 of the sphere) into a Zarr store, chunk by chunk (a rerun resumes);
:func:`spectralshell.open_sweep` reads it back, checking every chunk, as a labelled
``xarray.Dataset``; :mod:`spectralshell.plots.sweep_plot` draws its minimum-tau map.
"""

import sys
from pathlib import Path

import spectralshell as ss
from spectralshell.plots import sweep_plot

scene = Path(sys.argv[0]).resolve().with_name("map.toml")  # next to this script
ss.sweep(scene, executor="serial", out="map.zarr")  # or executor="processes" / "dask"

ds = ss.open_sweep("map.zarr")
print(ds)
sweep_plot.save(ds, "sweep_map.png")
