"""Component-error tables in CSV with ISO 230-1 column names, in and out.

Layout, one file per axis (so tables from laser software or a controller's pitch-error
compensation can be brought in axis by axis)::

    x_mm,EXX_um,EYX_um,EZX_um,EAX_urad,EBX_urad,ECX_urad
    0,0.0,0.0,0.0,1.2,-3.4,0.5
    50,1.1,0.3,-0.2,1.3,-3.1,0.7

The first column is the axis position (``<axis>_mm`` for linear axes, ``<axis>_deg`` for
rotary ones); the others are any subset of that axis's six component errors, each named
by its ISO 230-1 name and its unit: ``_um`` for the translational ones (``EXX``, ``EYX``,
``EZX``: second letter X, Y or Z), ``_urad`` for the angular ones (``EAX``, ``EBX``,
``ECX``). The bare ISO name (``EXX``) is read too, in the same units, as laser software
and the files of earlier versions write it; a suffix that contradicts the name's unit
(``EAX_um``) is refused. Position-independent errors go in one more file,
``name,value,unit`` (``EC0Y,12.5,urad``; ``name,value`` is read too). Every cell must be a
finite number; an error names file, line and column.

The model's extension terms (backlash, periodic, thermal) go to ``terms.json`` beside the
tables (:func:`export_model`, :func:`import_model`): the tables alone are the rigid
geometry. A term the file cannot carry exactly is refused at export, by name.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import (
    Component,
    GeometricErrors,
    Table,
    component_names,
    location_names,
)
from volumetric.model.machine import Axis, Machine
from volumetric.model.model import (
    BacklashTerm,
    DynamicThermalTerm,
    MachineModel,
    PeriodicTerm,
    Term,
    ThermalTerm,
)
from volumetric.plausible.columns import unit_column_problem
from volumetric.plausible.files import decode_text, wrong_file

UNITS = {"um": "µm", "urad": "µrad"}


def position_column(axis: Axis) -> str:
    return f"{axis.key}_{'mm' if axis.kind == 'linear' else 'deg'}"


def unit_of(name: str) -> str:
    """``um`` or ``urad``: ISO 230-1 names say it by their second letter (EXX, EX0C: a
    displacement along X; EAX, EC0Y: a rotation about A's axis x)."""
    return "um" if name[1] in "XYZ" else "urad"


def error_column(name: str) -> str:
    """The header of a component error's column: its ISO 230-1 name and its unit."""
    return f"{name}_{unit_of(name)}"


def _split_unit(column: str, source: str) -> str:
    """The ISO 230-1 name of a column header (``EXX_um`` or ``EXX``); a unit suffix that
    contradicts the name is refused rather than read in the wrong unit."""
    name, _, unit = column.rpartition("_")
    if not name or unit not in UNITS:
        return column
    if unit != unit_of(name):
        want = unit_of(name)
        raise ComponentErrorSpecError(
            f"{source}: column {column!r}: {name} is in {UNITS[want]} ({name}_{want}), "
            f"not {UNITS[unit]}")
    return name


_ISO_NAME = re.compile(r"^E[XYZABC](?:[XYZABC]|0[XYZABC])[0-9]*$")


def _wanted_units(header: list[str]) -> dict[str, str]:
    """The unit each column of a table header should carry, by its stem: an axis
    position mm (degrees for a rotary axis), an ISO 230-1 error µm or µrad."""
    wanted = {k: "mm" for k in ("x", "y", "z")} | {k: "deg" for k in ("a", "b", "c")}
    for col in header:
        stem = col.strip().rpartition("_")[0]
        if _ISO_NAME.match(stem):
            wanted[stem] = unit_of(stem)
        elif stem[:1] in "xyz" and stem[1:].isdigit():
            wanted[stem] = "mm"
    return wanted


def export_tables(
    machine: Machine, errors: GeometricErrors, *, points: int = 21
) -> dict[str, str]:
    """CSV text per axis (keyed ``X``, ``Y``, ...) plus ``locations``.

    Components are sampled at ``points`` equally spaced positions over the travel.
    """
    out: dict[str, str] = {}
    for axis in machine.axes:
        names = [n for n in component_names(axis) if n in errors.components]
        if not names:
            continue
        q = np.linspace(axis.travel[0], axis.travel[1], points)
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([position_column(axis), *map(error_column, names)])
        values = [errors.components[n](q) for n in names]
        for i, qi in enumerate(q):
            w.writerow([f"{qi:.6g}", *(f"{v[i]:.6g}" for v in values)])
        out[axis.name] = buf.getvalue()
    if errors.locations:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["name", "value", "unit"])
        for name, value in sorted(errors.locations.items()):
            w.writerow([name, f"{value:.6g}", unit_of(name)])
        out["locations"] = buf.getvalue()
    return out


def _number(cell: str, where: str) -> float:
    try:
        v = float(cell)
    except ValueError:
        raise ComponentErrorSpecError(f"{where}: {cell!r} is not a number") from None
    if not math.isfinite(v):
        raise ComponentErrorSpecError(f"{where}: {cell!r} is not a finite number")
    return v


def _blocks(text: str) -> list[list[tuple[int, list[str]]]]:
    """The CSV blocks of a text: ``#`` lines (metadata) dropped, blocks separated by
    blank lines, each row with its line number."""
    blocks: list[list[tuple[int, list[str]]]] = []
    cur: list[tuple[int, list[str]]] = []
    for i, line in enumerate(text.splitlines(), start=1):
        if line.lstrip().startswith("#"):
            continue
        if not line.strip() or not line.replace(",", "").strip():
            if cur and not line.strip():
                blocks.append(cur)
                cur = []
            continue
        cur.append((i, next(csv.reader([line]))))
    if cur:
        blocks.append(cur)
    return blocks


def _read_block(source: str, block: list[tuple[int, list[str]]],
                by_column: Mapping[str, Axis], allowed_locations: set[str],
                comps: dict[str, Component], locs: dict[str, float]) -> None:
    """One table (axis or locations) into ``comps`` or ``locs``."""
    header = [h.strip() for h in block[0][1]]
    body = block[1:]
    if header in (["name", "value"], ["name", "value", "unit"]):
        for line, r in body:
            if len(r) != len(header):
                raise ComponentErrorSpecError(
                    f"{source}:{line}: expected {','.join(header)}")
            name = r[0].strip()
            if name not in allowed_locations:
                raise ComponentErrorSpecError(
                    f"{source}:{line}: {name!r} is not a location error of this machine "
                    f"({sorted(allowed_locations)})"
                )
            if len(r) == 3 and r[2].strip() != unit_of(name):
                raise ComponentErrorSpecError(
                    f"{source}:{line} column unit: {name} is in {unit_of(name)}, "
                    f"not {r[2].strip()!r}")
            locs[name] = _number(r[1].strip(), f"{source}:{line} column value")
        return
    slip = unit_column_problem(header, _wanted_units(header))
    if slip is not None:  # x_in, EAX_arcsec: the unit the numbers alone cannot tell
        raise ComponentErrorSpecError(f"{source}: {slip}")
    axis = by_column.get(header[0])
    if axis is None:
        raise ComponentErrorSpecError(
            f"{source}: first column {header[0]!r} is not an axis position column of "
            f"this machine ({sorted(by_column)})"
        )
    valid = set(component_names(axis))
    written = header  # for messages: the column as the file names it
    header = [header[0], *(_split_unit(col, source) for col in header[1:])]
    for col in header[1:]:
        if col not in valid:
            raise ComponentErrorSpecError(
                f"{source}: column {col!r} is not a component error of axis {axis.name} "
                f"({sorted(valid)})"
            )
    if len(set(header)) != len(header):
        raise ComponentErrorSpecError(f"{source}: a column appears twice in {header}")
    if not body:
        raise ComponentErrorSpecError(f"{source}: no rows")
    for line, r in body:
        if len(r) != len(header):
            raise ComponentErrorSpecError(
                f"{source}:{line}: {len(r)} cells, the header has {len(header)}"
            )
    # a column of empty cells is one the file marks as unknown (not identified): no table
    empty = [all(not r[j].strip() for _, r in body) for j in range(len(header))]
    data = np.empty((len(body), len(header)))
    for k, (line, r) in enumerate(body):
        for j, cell in enumerate(r):
            if j and empty[j]:
                continue
            data[k, j] = _number(cell.strip(), f"{source}:{line} column {written[j]}")
    try:
        for j, col in enumerate(header[1:], start=1):
            if not empty[j]:
                comps[col] = Table(tuple(data[:, 0]), tuple(data[:, j]))
    except ComponentErrorSpecError as exc:
        raise ComponentErrorSpecError(f"{source}: {exc}") from None


def import_tables(machine: Machine, files: Iterable[tuple[str, str]]) -> GeometricErrors:
    """Component and location errors from CSV texts.

    Parameters
    ----------
    machine : Machine
    files : iterable of (source name, CSV text)

    Raises
    ------
    ComponentErrorSpecError
        Naming the file, line and column of the first problem.
    """
    comps: dict[str, Component] = {}
    locs: dict[str, float] = {}
    by_column = {position_column(a): a for a in machine.axes}
    allowed_locations = set(location_names(machine))
    for source, text in files:
        blocks = _blocks(text)
        if not blocks:
            raise ComponentErrorSpecError(f"{source}: empty file")
        for block in blocks:
            _read_block(source, block, by_column, allowed_locations, comps, locs)
    errors = GeometricErrors(comps, locs)
    errors.check(machine)
    return errors


def read_table_files(paths: Iterable[Path]) -> list[tuple[str, str]]:
    """(name, text) of each file, with a clear error for unreadable ones. A directory
    stands for what an export wrote there: its ``*.csv`` and :data:`TERMS_FILE`."""
    out = []
    for p in paths:
        p = Path(p)
        inside = (sorted(p.glob("*.csv")) + [q for q in [p / TERMS_FILE] if q.is_file()]
                  if p.is_dir() else [p])
        if not inside:
            raise ComponentErrorSpecError(f"{p}: a directory without tables (*.csv)")
        for q in inside:
            try:
                raw = q.read_bytes()
            except OSError as exc:
                raise ComponentErrorSpecError(f"{q}: cannot read ({exc.strerror})") from None
            other = wrong_file(raw[:4096], str(q), "tables") if q.name != TERMS_FILE else None
            if other is not None:  # a CEC program, a Fanuc file, a map, a model ...
                raise ComponentErrorSpecError(other)
            try:
                out.append((str(q), decode_text(raw, str(q))))
            except ValueError as exc:
                raise ComponentErrorSpecError(str(exc)) from None
    return out


def write_tables(tables: Mapping[str, str], directory: Path) -> list[Path]:
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for key, text in tables.items():
        p = directory / f"{key}.csv"
        p.write_text(text)
        written.append(p)
    return written


# --- extension terms ---------------------------------------------------------------------
# The model's terms (backlash, periodic, thermal expansion and drift, dynamic thermal with
# lags and a time column) go to one JSON file beside the CSV tables. JSON rather than CSV:
# a dynamic thermal term holds a list of regressors of its own length, each with its unit
# and a saved lag state that may be absent (null); a flat CSV would need sparse columns or
# a second file linked by row numbers. JSON writes each number as its shortest exact
# decimal, so the terms come back bit for bit.

TERMS_FILE = "terms.json"
TERMS_FORMAT = "ednc-terms/1"

REVERSAL_CONVENTION = (
    "reversal_um = error on a negative approach minus error on a positive approach, µm, "
    ">= 0 for an axis that lags behind its motion (the tool stops B/2 short on either side, "
    "protocol/README.md section 6); a map carries the correction's reversal, which is "
    "-reversal_um/1000 mm")

TERM_UNITS = {
    "reversal_um": "µm",
    "amplitude_um": "µm",
    "period_mm": "mm",
    "phase_rad": "rad",
    "t_ref_C": "°C",
    "q_min": "mm (the axis position where the expansion is zero)",
    "coefficient": "µm/(m·K) for thermal_expansion; µm/K for thermal_drift and for a "
                   "thermal_dynamic level or lag column; µm/h for a time column",
    "std": "the unit of its coefficient",
    "intercept_um": "µm",
    "t0_s": "s (origin of the time column)",
    "t_state_s": "s (time of the last fitted reading; null when none was saved)",
    "tau_s": "s (a lag's time constant; 0 for level and time columns)",
    "state_C": "°C (the lag's state at t_state_s; null when none was saved)",
    "input_C": "°C (the sensor's temperature at t_state_s; null when none was saved)",
}

_KINDS = (ThermalTerm, PeriodicTerm, BacklashTerm, DynamicThermalTerm)
_EFFECTS = "backlash, periodic, thermal_expansion, thermal_drift, thermal_dynamic"


def _term_label(index: int, term: object) -> str:
    """``term 2 (backlash of axis x)``: how messages name a term."""
    effect = {ThermalTerm: getattr(term, "kind", "thermal"), PeriodicTerm: "periodic",
              BacklashTerm: "backlash", DynamicThermalTerm: "thermal_dynamic"}.get(
                  type(term), type(term).__name__)
    axis = getattr(term, "axis", None)
    return f"term {index} ({effect}{f' of axis {axis}' if axis is not None else ''})"


def describe_term(term: Term) -> str:
    """One line saying what a term does, with its units."""
    a = term.axis
    if isinstance(term, BacklashTerm):
        return (f"backlash of axis {a}: reversal {term.reversal_um:g} µm; "
                f"{REVERSAL_CONVENTION}")
    if isinstance(term, PeriodicTerm):
        return (f"periodic error of axis {a}: E{a.upper()}{a.upper()} += "
                f"{term.amplitude_um:g} µm · sin(2π·{a}/{term.period_mm:g} mm + "
                f"{term.phase_rad:g} rad)")
    if isinstance(term, ThermalTerm):
        if term.kind == "thermal_drift":
            return (f"thermal drift along {a}: E{a.upper()}{a.upper()} += "
                    f"{term.coefficient:g} µm/K · ({term.sensor} − {term.t_ref_C:g} °C)")
        return (f"thermal expansion of axis {a}: E{a.upper()}{a.upper()} += "
                f"{term.coefficient:g} µm/(m·K) · ({term.sensor} − {term.t_ref_C:g} °C) · "
                f"({a} − {term.q_min:g} mm)")
    parts = []
    for c in term.columns:
        if c.kind == "time":
            parts.append(f"{c.coefficient:g} µm/h · hours since t0_s")
        elif c.kind == "lag":
            parts.append(f"{c.coefficient:g} µm/K · lag({c.sensor}, τ {c.tau_s:g} s)")
        else:
            parts.append(f"{c.coefficient:g} µm/K · {c.sensor}")
    return (f"lagged (dynamic) thermal drift along {a}: E{a.upper()}{a.upper()} += "
            f"{term.intercept_um:g} µm" + "".join(f" + {p}" for p in parts))


def _non_finite(value: Any, path: str) -> str | None:
    """The key path of the first NaN or infinity in a term's JSON, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return path
    if isinstance(value, Mapping):
        for k, v in value.items():
            found = _non_finite(v, f"{path}.{k}" if path else str(k))
            if found:
                return found
    if isinstance(value, list):
        for i, v in enumerate(value):
            found = _non_finite(v, f"{path}[{i}]")
            if found:
                return found
    return None


def _terms_json(model_name: str, terms: Iterable[Term]) -> list[dict[str, Any]]:
    """The model's own JSON of each term (so the file and a model file agree)."""
    return list(MachineModel(model_name, GeometricErrors(), tuple(terms)).to_json()["terms"])


def export_terms(machine: Machine, model: MachineModel) -> str:
    """The text of :data:`TERMS_FILE`: every extension term of ``model``, exactly.

    Raises
    ------
    ComponentErrorSpecError
        Naming the first term the file cannot carry exactly (a kind it does not know, a
        NaN or infinite value, an axis the machine does not have): nothing is dropped in
        silence.
    """
    keys = {a.key for a in machine.axes}
    out = []
    for i, t in enumerate(model.terms):
        label = _term_label(i, t)
        if not isinstance(t, _KINDS):
            raise ComponentErrorSpecError(
                f"cannot export {label}: the tables format carries {_EFFECTS} terms only, "
                "not this kind; nothing written")
        if t.axis not in keys:
            raise ComponentErrorSpecError(
                f"cannot export {label}: machine {machine.name!r} has axes {sorted(keys)}")
        (data,) = _terms_json(model.machine, (t,))
        bad = _non_finite(data, "")
        if bad:
            raise ComponentErrorSpecError(
                f"cannot export {label}: {bad} is {_lookup(data, bad)!r}; the tables format "
                "carries finite numbers only; nothing written")
        # the file must give back what the model holds: check by reading it again
        (again,) = _terms_from_json([data], "export")
        if _terms_json(model.machine, (again,)) != [data]:
            raise ComponentErrorSpecError(
                f"cannot export {label}: it does not survive its own JSON; nothing written")
        out.append({"description": describe_term(t), **data})
    doc = {
        "format": TERMS_FORMAT,
        "machine": model.machine or machine.name,
        "description": (
            "Extension terms of the machine model (ednc-model/1 'terms', effect names of "
            "formats.md section 3), written by `ednc tables export` beside the per-axis "
            "component-error tables and locations.csv; `ednc tables import` reads them "
            "back. Each term adds to the named axis's positioning error at the given "
            "temperatures; backlash is applied by direction. Backlash sign convention: "
            + REVERSAL_CONVENTION + "."),
        "units": TERM_UNITS,
        "terms": out,
        # the rest of the model, so that an import gives it back whole: the fit's
        # tool-tip offsets (the readings' zero, which `ednc predict` adds) and its other
        # statistics, and the exact component functions the CSV tables sample
        "offsets_um": _finite(dict(offsets) if isinstance(
            offsets := model.info.get("offsets_um"), Mapping) else {}),
        "info": _finite(dict(model.info)),
        "geometry": model.geometry.to_json(),
        "geometry_note": (
            "the exact component functions; the CSV tables sample them. `ednc tables "
            "import` uses these when every CSV value still equals them (to 1e-4 of its "
            "column's largest value), and the CSV tables when a table was edited"),
    }
    return json.dumps(doc, indent=1, ensure_ascii=False) + "\n"


def _finite(value: Any) -> Any:
    """A JSON value with NaN and infinities replaced by null (JSON has neither)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, Mapping):
        return {str(k): _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value


def _lookup(data: Mapping[str, Any], path: str) -> Any:
    """The value at a key path of :func:`_non_finite` (for the message)."""
    v: Any = data
    for part in path.replace("[", ".[").split("."):
        v = v[int(part[1:-1])] if part.startswith("[") else v[part]
    return v


def _terms_from_json(raw: list[Any], source: str) -> tuple[Term, ...]:
    """Terms parsed by the model's own reader, with the source in the message."""
    cleaned = [{k: v for k, v in t.items() if k != "description"} if isinstance(t, Mapping)
               else t for t in raw]
    try:
        return MachineModel.from_json({"components": {}, "locations": {},
                                       "terms": cleaned}).terms
    except ComponentErrorSpecError as exc:
        raise ComponentErrorSpecError(f"{source}: {exc}") from None


def _refuse_constant(name: str) -> float:
    raise ComponentErrorSpecError(f"{name} is not a finite number")


def import_terms(machine: Machine, source: str, text: str) -> tuple[Term, ...]:
    """The extension terms of a :data:`TERMS_FILE` text (see :func:`read_terms_file`)."""
    return read_terms_file(machine, source, text)[0]


def read_terms_file(machine: Machine, source: str, text: str
                    ) -> tuple[tuple[Term, ...], dict[str, Any], GeometricErrors | None]:
    """The extension terms of a :data:`TERMS_FILE` text, the model's info (with its
    offsets) and its exact geometry, when the file holds them (files of earlier versions
    hold neither: ``{}`` and None).

    Raises
    ------
    ComponentErrorSpecError
        Naming the file (and the term) when it is not a terms file, is of another
        machine, or holds a term the model cannot read or an axis the machine lacks.
    """
    try:
        doc = json.loads(text, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise ComponentErrorSpecError(
            f"{source}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except ComponentErrorSpecError as exc:
        raise ComponentErrorSpecError(f"{source}: {exc}") from None
    if not isinstance(doc, Mapping) or doc.get("format") != TERMS_FORMAT:
        raise ComponentErrorSpecError(
            f"{source}: not a terms file (expected \"format\": \"{TERMS_FORMAT}\", as "
            f"`ednc tables export` writes {TERMS_FILE})")
    name = doc.get("machine")
    if name and name != machine.name:
        raise ComponentErrorSpecError(
            f"{source}: the terms are of machine {name!r}, the description of "
            f"{machine.name!r}")
    raw = doc.get("terms")
    if not isinstance(raw, list):
        raise ComponentErrorSpecError(f"{source}: 'terms' must be a list")
    terms = _terms_from_json(raw, source)
    keys = {a.key for a in machine.axes}
    for i, t in enumerate(terms):
        if t.axis not in keys:
            raise ComponentErrorSpecError(
                f"{source}: {_term_label(i, t)}: machine {machine.name!r} has axes "
                f"{sorted(keys)}")
    info = doc.get("info", {})
    if not isinstance(info, Mapping):
        raise ComponentErrorSpecError(f"{source}: 'info' must be an object")
    info = dict(info)
    offsets = doc.get("offsets_um")
    if offsets is not None:
        if not isinstance(offsets, Mapping) or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool)
                for v in offsets.values()):
            raise ComponentErrorSpecError(
                f"{source}: 'offsets_um' must map OFFSET_X ... to numbers (µm)")
        info["offsets_um"] = {str(k): float(v) for k, v in offsets.items()}
    geometry = None
    if doc.get("geometry") is not None:
        try:
            geometry = GeometricErrors.from_json(doc["geometry"])
        except ComponentErrorSpecError as exc:
            raise ComponentErrorSpecError(f"{source}: geometry: {exc}") from None
    return terms, info, geometry


def export_model(machine: Machine, model: MachineModel, *, points: int = 21
                 ) -> dict[str, str]:
    """Every file of a model's export, keyed by file name: ``X.csv``, ... (the geometry
    sampled at ``points`` positions per axis), ``locations.csv`` and :data:`TERMS_FILE`.

    The terms are checked first, so a refused term leaves nothing half written.
    """
    terms = export_terms(machine, model)
    files = {f"{k}.csv": v for k, v in export_tables(machine, model.geometry,
                                                      points=points).items()}
    files[TERMS_FILE] = terms
    return files


def import_model(machine: Machine, files: Iterable[tuple[str, str]]) -> MachineModel:
    """A model from exported files: ``*.json`` is the terms file (at most one), the rest
    are CSV tables. Without a terms file (exports of earlier versions) the model is rigid.
    """
    files = list(files)
    json_files = [(s, t) for s, t in files if s.lower().endswith(".json")]
    if len(json_files) > 1:
        raise ComponentErrorSpecError(
            f"more than one terms file: {', '.join(s for s, _ in json_files)}")
    geometry = import_tables(machine, [(s, t) for s, t in files
                                       if not s.lower().endswith(".json")])
    terms: tuple[Term, ...] = ()
    info: dict[str, Any] = {}
    exact = None
    if json_files:
        terms, info, exact = read_terms_file(machine, *json_files[0])
    if exact is not None and _agrees(geometry, exact):
        geometry = exact  # the tables are the exact functions' samples: take those
    info["source"] = [s for s, _ in files]
    return MachineModel(machine.name, geometry, terms, info)


def _agrees(tables: GeometricErrors, exact: GeometricErrors) -> bool:
    """Whether every table still holds the exact functions' values at its positions (to
    1e-4 of its largest value: the CSV writes 6 significant digits) and the locations
    and the set of components are the same."""
    if set(tables.components) != set(exact.components):
        return False
    if set(tables.locations) != set(exact.locations):
        return False
    for name, t in tables.components.items():
        if not isinstance(t, Table):
            return False
        p = np.asarray(t.positions)
        v = np.asarray(t.values)
        want = np.asarray(exact.components[name](p), dtype=float)
        if np.abs(want - v).max() > 1e-4 * max(float(np.abs(want).max()), 1e-6):
            return False
    return all(abs(v - exact.locations[n]) <= 1e-5 * max(abs(v), 1e-6)
               for n, v in tables.locations.items())


def write_files(files: Mapping[str, str], directory: Path) -> list[Path]:
    """Write each ``{file name: text}`` into ``directory`` (created if needed)."""
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in files.items():
        p = directory / name
        p.write_text(text, encoding="utf-8")
        written.append(p)
    return written
