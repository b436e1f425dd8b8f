"""Stage 4, solvers: eigen-solvers and sweeps over Hill matrices; they never know the model."""
