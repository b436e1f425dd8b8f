"""
Scenes and the model registry
=============================

:func:`spectralshell.models` lists the registered models (the README's "Adding a model" shows how
to add one); :func:`spectralshell.run_scene` plans a scene (a TOML file, string or mapping) and
computes only the tasks it asks for, here the default scene of ``spectralshell demo``.
"""

import tomllib
from importlib import resources

import spectralshell as ss
from spectralshell.plots import ince_strutt

print(ss.models())

text = resources.files("spectralshell").joinpath("params/scenes/demo.toml").read_text()
scene = tomllib.loads(text)
scene["tongues"]["kappa"] = {"start": 0.0, "stop": 3.0, "num": 61}  # a coarse diagram
results = ss.run_scene(scene, workers=1)
for task, result in results.items():
    print(f"--- {task}\n{result.summary()}")
ince_strutt.save([results["tongues"]], "scene_tongues.png")
