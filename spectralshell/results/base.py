"""The base of every result object: JSON form, text summary, a JSON file round trip, short repr."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._validate import require_output_file
from .._version import __version__
from ..errors import ParameterError
from .notebook import html_table, result_html
from .records import RECORDS, decode, fields_of

if TYPE_CHECKING:
    import xarray as xr

#: Lines of a result's repr at most (the first lines of its summary).
REPR_LINES = 20


class Plottable:
    """A result with a picture: :meth:`plot` draws it (``spectralshell.plot.draw``)."""

    def plot(self, ax=None, **options: Any):
        """Draw this result on ``ax`` (None: on a new figure made without pyplot, so the
        backend is never changed) and return the Axes; ``options`` as for the function of
        ``spectralshell.plot`` that draws this type."""
        # The drawing lives in the plots stage, downstream of the results: it is named by
        # module path (as pandas' DataFrame.plot finds its backend), so no results module
        # imports a later stage.
        from importlib import import_module

        return import_module("spectralshell.plots.public").draw(self, ax, **options)


def format_params(params: dict[str, Any]) -> str:
    """Parameters as one line, 'kappa = 0.3  nu = 0.1' (floats with %g); those that are None
    (an option not used, e.g. spatial_mode) are left out."""
    return "  ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                     for k, v in params.items() if v is not None)


def _one_line(exc: Exception) -> str:
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


def _subclass_named(cls: type, name: str) -> type | None:
    """``cls`` or its (imported) subclass called ``name``, else None."""
    if cls.__name__ == name:
        return cls
    return next((found for sub in cls.__subclasses__()
                 if (found := _subclass_named(sub, name)) is not None), None)


class Result:
    """Base of the result objects (frozen dataclasses, declared with ``repr=False``).

    A subclass defines :meth:`to_dict` (its JSON form, printed by ``--json``), :meth:`summary`
    (the text the command line prints), :meth:`to_xarray` (a labelled Dataset) and
    ``_html_table`` (the table of its notebook HTML, :meth:`_repr_html_`), and lists in
    ``record_types`` the dataclasses its fields hold besides the record types of
    :mod:`spectralshell.results.records`. :meth:`save` and :meth:`load` store every field in a
    JSON file, with the type name and the package version.
    """

    record_types: tuple[type, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (``spectralshell ... --json``)."""
        raise NotImplementedError

    def summary(self) -> str:
        """The human text of the result (what the command line prints)."""
        raise NotImplementedError

    def to_xarray(self) -> xr.Dataset:
        """The result as an ``xarray.Dataset``: coordinates and variables with ``units`` and
        ``long_name``, params, provenance and warnings as JSON strings in the attrs
        (:mod:`spectralshell.results.notebook`); it round-trips through NetCDF."""
        raise NotImplementedError

    def _html_table(self) -> tuple[list[str], list[list[Any]]]:
        """Headers and rows of the HTML table (:meth:`_repr_html_`): the key numbers."""
        raise NotImplementedError

    def _repr_html_(self) -> str:
        """HTML for a notebook: the type, the first line of :meth:`summary`, a table of the key
        numbers with their errors (at most :data:`~.notebook.HTML_ROWS` rows) and the
        warnings."""
        caption = self.summary().splitlines()[0]
        return result_html(type(self).__name__, caption, html_table(*self._html_table()),
                           getattr(self, "warnings", ()))

    def __repr__(self) -> str:
        lines = self.summary().splitlines()
        if len(lines) > REPR_LINES:
            more = len(lines) - REPR_LINES + 1
            lines = lines[:REPR_LINES - 1] + [f"  ... ({more} more lines: .summary())"]
        return f"<{type(self).__name__}> " + "\n".join(lines)

    def save(self, path: str | Path) -> Path:
        """Write every field to the JSON file ``path`` (a new or existing regular file ending in
        .json, which is replaced), with the type name and the package version; :meth:`load`
        reads it back. Returns the path."""
        path = require_output_file("path", path, (".json",))
        data = {"type": type(self).__name__, "version": __version__, "fields": fields_of(self)}
        path.write_text(json.dumps(data, allow_nan=False) + "\n")
        return path

    @classmethod
    def load(cls, path: str | Path):
        """The result that :meth:`save` wrote to ``path``: an instance of this class (or of a
        subclass). Raises :class:`~spectralshell.errors.ParameterError`, naming the path and
        what is wrong, for a file that cannot be read, is not JSON, holds another type, or
        lacks or has damaged fields."""
        where = f"result file {str(path)!r}"
        data = _read_json(path, where)
        kind = _subclass_named(cls, data["type"])
        if kind is None:
            raise ParameterError(f"{where} holds a {data['type']}, not a {cls.__name__}")
        stored = data["fields"]
        wrong = _field_mismatch(kind, stored)
        if wrong:
            raise ParameterError(f"{where} {wrong}")
        types = {**RECORDS, **{t.__name__: t for t in kind.record_types}}
        values = {}
        for name, raw in stored.items():
            try:
                values[name] = decode(raw, types)
            except (KeyError, TypeError, ValueError) as exc:
                raise ParameterError(f"{where}: field {name!r} is damaged "
                                     f"({_one_line(exc)})") from None
        result = kind(**values)
        try:  # every field in use: a value of the wrong kind fails here, not later
            result.to_dict()
            result.summary()
        except (AttributeError, IndexError, KeyError, TypeError, ValueError) as exc:
            raise ParameterError(f"{where} has a damaged field ({_one_line(exc)})") from None
        return result


def _read_json(path: str | Path, where: str) -> dict[str, Any]:
    """The JSON object in ``path`` with a str 'type' and an object 'fields'; else ParameterError
    (``where`` names the file)."""
    try:
        data = json.loads(Path(path).read_text())
    except OSError as exc:
        raise ParameterError(f"{where} cannot be read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise ParameterError(f"{where} is not a text file") from None
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{where} is not valid JSON: {exc.msg} at line {exc.lineno}, "
                             f"column {exc.colno}") from None
    if not (isinstance(data, dict) and isinstance(data.get("type"), str)
            and isinstance(data.get("fields"), dict)):
        raise ParameterError(f"{where} is not a saved spectralshell result: no 'type' and "
                             "'fields'")
    return data


def _field_mismatch(kind: type, stored: dict[str, Any]) -> str | None:
    """What is wrong with the field names ``stored`` for the dataclass ``kind``: a required
    field missing or an unknown one (None if nothing)."""
    fields = {f.name: f for f in dataclasses.fields(kind)}
    for name, f in fields.items():
        if (name not in stored and f.default is dataclasses.MISSING
                and f.default_factory is dataclasses.MISSING):
            return f"lacks field {name!r} of {kind.__name__}"
    unknown = [name for name in stored if name not in fields]
    return f"has unknown field {unknown[0]!r} of {kind.__name__}" if unknown else None
