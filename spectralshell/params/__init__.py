"""Stage 1: parameters (frozen dataclasses per model), presets, scenes and the scene planner."""
