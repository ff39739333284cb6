"""Read a tyre property file (`.tir`, the MF-Tyre/MFeval/Adams format) into `MagicFormulaTire`.

The format: `[SECTION]` headers; `NAME = value` lines, the value a number or a quoted string;
comments from `$` or `!` to the end of the line; `{...}` headers opening tables of bare numbers
(read over). `[UNITS]` names the length and force units (converted to SI); angles must be
radians. `[MODEL] FITTYP` names the Magic Formula version: 61 (MF 6.1), or 6 and 21 (MF 5.2 /
PAC2002, whose force equations at zero camber and nominal pressure are 6.1's with PKY4 = 2); a
file without FITTYP whose `PROPERTY_FILE_FORMAT` is 'PAC2002' (as Adams and Project Chrono write
them) is MF 5.2. A name may recur in another section (MASS in [UNITS] and [INERTIA]) unless the
forces read it.

Refused (InputError "FILE:LINE: problem", no warnings): a malformed line, a non-numeric value, a
name given twice in a section (or in two, for a coefficient the forces read), an unknown version
or unit, a missing required section or coefficient, a negative or inverted load range. Accepted
files warn once (`TirWarning`) about the coefficients they set that our equations ignore, and
once about the coefficients they lack, which take their neutral values (`mf_coefficients.neutral`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

from chassistune.errors import InputError
from chassistune.plants.mf_coefficients import (
    LATERAL_ONLY,
    REQUIRED_LATERAL,
    REQUIRED_LONGITUDINAL,
    MagicFormulaTire,
    neutral,
    tir_name,
)

FITTYP_VERSIONS = {61: "MF 6.1", 6: "MF 5.2", 21: "MF 5.2"}
"""FITTYP values accepted, and the version each names (all evaluated by the MF 6.1 equations)."""

FORMAT_FITTYP = {"PAC2002": 6}
"""The FITTYP a file without one has, by its PROPERTY_FILE_FORMAT."""

LENGTH_UNITS_M = {"meter": 1.0, "m": 1.0, "mm": 1e-3, "millimeter": 1e-3, "cm": 1e-2,
                  "centimeter": 1e-2, "inch": 0.0254, "in": 0.0254}  # fmt: skip
FORCE_UNITS_N = {"newton": 1.0, "n": 1.0, "kn": 1e3, "kilonewton": 1e3, "lbf": 4.4482216152605,
                 "pound_force": 4.4482216152605}  # fmt: skip
ANGLE_UNITS = ("radian", "radians", "rad")

REQUIRED_SECTIONS = ("MODEL", "DIMENSION", "VERTICAL", "LONGITUDINAL_COEFFICIENTS")
"""Sections every file needs (and LATERAL_COEFFICIENTS for lateral forces)."""

_FORCES = ("FNOMIN", "FZMIN", "FZMAX")
_LENGTHS = ("UNLOADED_RADIUS",)
_STIFFNESSES = ("LONGITUDINAL_STIFFNESS", "LATERAL_STIFFNESS")
_OPTIONAL = (
    "FZMIN", "FZMAX", "LONGITUDINAL_STIFFNESS", "PCFX1", "PCFX2", "PTX1", "PTX2", "PTX3", "LSGKP",
    "LATERAL_STIFFNESS", "PCFY1", "PCFY2", "PTY1", "PTY2", "LSGAL",
)  # fmt: skip
"""Not force coefficients: absent (no load limits; no relaxation length, or one independent of
the load; MF 5.2's relaxation terms in an MF 6.1 file, and the reverse), without a warning."""


class TirWarning(UserWarning):
    """An accepted TIR file's coefficients that are ignored or absent (one line each)."""


@dataclass(frozen=True)
class _Entry:
    value: float | str
    line: int
    section: str
    repeated_at: int = 0
    """The line of the same name in a later section (0: none)."""


@dataclass(frozen=True)
class TirFile:
    """A TIR file as read: its coefficients, its Magic Formula version, and the names of the
    coefficients it sets that the equations ignore, and of those it lacks (neutral values)."""

    tire: MagicFormulaTire
    fittyp: int
    version: str
    ignored: tuple[str, ...]
    absent: tuple[str, ...]


def read_tir(path: str, lateral: bool = False) -> MagicFormulaTire:
    """The MF coefficients of the TIR file at `path` (the lateral ones only if `lateral`), with
    one `TirWarning` each for the ignored and the absent coefficients."""
    contents = read_tir_file(path, lateral)
    for names, what in ((contents.ignored, "ignored (camber, pressure, moments, turn slip, ...)"),
                        (contents.absent, "absent, their neutral values used")):  # fmt: skip
        if names:
            warnings.warn(
                TirWarning(f"{path}: {len(names)} coefficients {what}: {' '.join(names)}"),
                stacklevel=2,
            )
    return contents.tire


def read_tir_file(path: str, lateral: bool = False) -> TirFile:
    """The TIR file at `path` as read, without warnings (`read_tir` gives them)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            lines = fh.read().splitlines()
    except OSError as exc:
        raise InputError("tire", f"cannot read {path!r}: {exc.strerror or exc}") from None
    entries, sections = _parse(path, lines)
    end = f"{path}:{len(lines)}"
    for section in (*REQUIRED_SECTIONS, *(("LATERAL_COEFFICIENTS",) if lateral else ())):
        if section not in sections:
            raise InputError(end, f"end of file without a [{section}] section")
    fittyp = _version(path, entries, end)
    if fittyp not in FITTYP_VERSIONS:
        known = ", ".join(f"{k} ({v})" for k, v in FITTYP_VERSIONS.items())
        raise InputError(_at(path, entries["FITTYP"]), f"FITTYP = {fittyp:g} is not a Magic "
                         f"Formula version read here (accepted: {known})")  # fmt: skip
    length_m, force_n = _units(path, entries)
    required = REQUIRED_LONGITUDINAL + (REQUIRED_LATERAL if lateral else ())
    mf52 = FITTYP_VERSIONS[int(fittyp)].startswith("MF 5.2")
    values: dict[str, float] = {}
    read: set[str] = set()
    absent: list[str] = []
    for f in dataclasses.fields(MagicFormulaTire):
        name = tir_name(f.name)
        if name in LATERAL_ONLY and not lateral:
            values[f.name] = neutral(name)
            continue
        read.add(name)
        _check_unique(path, entries, name)
        if name == "PKY4" and mf52:
            values[f.name] = neutral(name)  # MF 5.2's constant 2
        elif name in entries:
            values[f.name] = _number(path, entries, name, end) * _si_factor(name, length_m, force_n)
        elif name in required:
            raise InputError(end, f"end of file without {name}, which the forces need")
        else:
            values[f.name] = neutral(name)
            absent += [] if name in _OPTIONAL else [name]
    tire = MagicFormulaTire(**values)
    _check_ranges(path, entries, tire)
    ignored = sorted(
        name
        for name, entry in entries.items()
        if entry.section.endswith("_COEFFICIENTS")
        and name not in read
        and not (name in LATERAL_ONLY and not lateral)
        and entry.value != neutral(name)
    )
    version = FITTYP_VERSIONS[int(fittyp)]
    return TirFile(tire, int(fittyp), version, tuple(ignored), tuple(absent))


def _si_factor(name: str, length_m: float, force_n: float) -> float:
    """What a value of `name` in the file's units is multiplied by to be in SI."""
    if name in _FORCES:
        return force_n
    if name in _LENGTHS:
        return length_m
    return force_n / length_m if name in _STIFFNESSES else 1.0


def _at(path: str, entry: _Entry) -> str:
    return f"{path}:{entry.line}"


def _parse(path: str, lines: list[str]) -> tuple[dict[str, _Entry], set[str]]:
    """(NAME -> entry, the section names) of the file's lines; InputError on a malformed one."""
    entries: dict[str, _Entry] = {}
    sections: set[str] = set()
    section = ""
    in_table = False
    for number, raw in enumerate(lines, start=1):
        text = _strip_comment(raw).strip()
        if not text:
            continue
        where = f"{path}:{number}"
        if text.startswith("["):
            if not text.endswith("]") or len(text) < 3:
                raise InputError(where, f"malformed section header {text!r}")
            section = text[1:-1].strip().upper()
            sections.add(section)
            in_table = False
            continue
        if text.startswith("{"):
            in_table = True  # a table's column header: bare rows of numbers follow
            continue
        name, sep, value = text.partition("=")
        name = name.strip().upper()
        if not sep:
            if in_table and all(_is_number(t) for t in text.split()):
                continue
            raise InputError(where, f"expected NAME = value, got {text!r}")
        if not section:
            raise InputError(where, f"{name} before the first [SECTION] header")
        if not name.replace("_", "").isalnum():
            raise InputError(where, f"malformed name {name!r}")
        entry = _Entry(_value(where, name, value.strip()), number, section)
        first = entries.get(name)
        if first is None:
            entries[name] = entry
        elif first.section == section:
            raise InputError(where, f"{name} given twice (first on line {first.line})")
        elif not first.repeated_at:
            entries[name] = dataclasses.replace(first, repeated_at=number)
    return entries, sections


def _check_unique(path: str, entries: dict[str, _Entry], name: str) -> None:
    """InputError if `name`, which the forces read, is given in two sections."""
    entry = entries.get(name)
    if entry is not None and entry.repeated_at:
        raise InputError(f"{path}:{entry.repeated_at}", f"{name} given again in another section "
                         f"(first on line {entry.line}, in [{entry.section}])")  # fmt: skip


def _version(path: str, entries: dict[str, _Entry], end: str) -> float:
    """FITTYP, or the one PROPERTY_FILE_FORMAT implies when FITTYP is absent."""
    file_format = entries.get("PROPERTY_FILE_FORMAT")
    if "FITTYP" not in entries and file_format is not None:
        fittyp = FORMAT_FITTYP.get(str(file_format.value).strip().upper())
        if fittyp is None:
            known = ", ".join(FORMAT_FITTYP)
            raise InputError(_at(path, file_format), f"no FITTYP, and PROPERTY_FILE_FORMAT = "
                             f"{file_format.value!r} names no Magic Formula version read here "
                             f"(known: {known})")  # fmt: skip
        return float(fittyp)
    return _number(path, entries, "FITTYP", end)


def _strip_comment(line: str) -> str:
    """The line up to a `$` or `!` comment outside quotes."""
    quote = ""
    for i, ch in enumerate(line):
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "$!":
            return line[:i]
    return line


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def _value(where: str, name: str, text: str) -> float | str:
    """A value: a quoted string, or a finite number."""
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    if not _is_number(text):
        raise InputError(where, f"{name} = {text!r} is not a finite number (nor a quoted string)")
    return float(text)


def _number(path: str, entries: dict[str, _Entry], name: str, end: str) -> float:
    """The numeric value of `name` (InputError if absent or a string)."""
    if name not in entries:
        raise InputError(end, f"end of file without {name}")
    entry = entries[name]
    if not isinstance(entry.value, float):
        raise InputError(_at(path, entry), f"{name} = {entry.value!r} is not a number")
    return entry.value


def _units(path: str, entries: dict[str, _Entry]) -> tuple[float, float]:
    """(metres per length unit, newtons per force unit) of [UNITS] (SI when absent)."""
    factors = []
    for name, table in (("LENGTH", LENGTH_UNITS_M), ("FORCE", FORCE_UNITS_N)):
        entry = entries.get(name)
        unit = str(entry.value).strip().lower() if entry else next(iter(table))
        if entry is None or unit in table:
            factors.append(table[unit])
            continue
        raise InputError(_at(path, entry), f"{name} = {entry.value!r}: unknown unit "
                         f"(known: {', '.join(table)})")  # fmt: skip
    angle = entries.get("ANGLE")
    if angle is not None and str(angle.value).strip().lower() not in ANGLE_UNITS:
        raise InputError(_at(path, angle), f"ANGLE = {angle.value!r}: only radians are read")
    return factors[0], factors[1]


def _check_ranges(path: str, entries: dict[str, _Entry], tire: MagicFormulaTire) -> None:
    """InputError for a non-positive nominal load or radius, a negative or inverted load range."""
    for name, value in (("FNOMIN", tire.fnomin_n), ("UNLOADED_RADIUS", tire.unloaded_radius_m)):
        if not value > 0.0:
            raise InputError(_at(path, entries[name]), f"{name} must be positive, got {value:g}")
    if tire.fzmin_n < 0.0:
        raise InputError(_at(path, entries["FZMIN"]),
                         f"FZMIN must not be negative, got {tire.fzmin_n:g}")  # fmt: skip
    if not tire.fzmax_n > tire.fzmin_n:
        raise InputError(_at(path, entries["FZMAX"]), f"load range inverted or empty: FZMAX "
                         f"= {tire.fzmax_n:g} <= FZMIN = {tire.fzmin_n:g}")  # fmt: skip
