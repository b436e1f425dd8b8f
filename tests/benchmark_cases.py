"""Helpers shared by the benchmark tests (tests/test_benchmark*.py): a user's run written as
score's CSV, and the check that the CLI writes the bytes of a computation made in Python."""

import numpy as np

from spectralshell.cli import main
from spectralshell.results.benchmark import write_csv, write_netcdf


def user_csv(path, t, columns):
    """``columns`` ({name: values} at times t) as a user's CSV at ``path`` (with a comment)."""
    names = list(columns)
    rows = np.column_stack([t] + [columns[n] for n in names])
    path.write_text("# my IB run\n" + ",".join(["t", *names]) + "\n"
                    + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    return path


def cli_writes(name, reference, tmp_path, capsys) -> str:
    """`benchmark write NAME --json` into tmp_path/cli, checked to be byte for byte the NetCDF
    and CSV of ``reference`` (the same computation from Python); its JSON output."""
    assert main(["benchmark", "write", name, "--out", str(tmp_path / "cli"), "--json"]) == 0
    out = capsys.readouterr().out
    write_netcdf(reference, tmp_path / "py.nc")
    write_csv(reference, tmp_path / "py.csv")
    for suffix in ("nc", "csv"):
        assert ((tmp_path / "cli" / f"{name}.{suffix}").read_bytes()
                == (tmp_path / f"py.{suffix}").read_bytes())
    return out
