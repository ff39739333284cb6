"""Load a rule base by built-in name (`deffao`, `classic`, `immune`) or from a user's TOML file.

Loaded rule bases are cached per (resolved path, modification time, size): editing a file is seen
on the next load, and repeated loads in one process cost nothing.
"""

from __future__ import annotations

import tomllib
from functools import lru_cache
from importlib import resources
from pathlib import Path

from chassistune.errors import InputError
from chassistune.fuzzy.rulebase import RuleBase
from chassistune.fuzzy.schema import rulebase_from_dict

_PACKAGE_DIR = "data/rulebases"


def builtin_names() -> tuple[str, ...]:
    """Names of the rule bases shipped with the package."""
    folder = resources.files("chassistune").joinpath(_PACKAGE_DIR)
    return tuple(
        sorted(p.name.removesuffix(".toml") for p in folder.iterdir() if p.name.endswith(".toml"))
    )


def builtin_path(name: str) -> Path:
    """The file of a built-in rule base."""
    return Path(str(resources.files("chassistune").joinpath(f"{_PACKAGE_DIR}/{name}.toml")))


def resolve(spec: str | Path, field: str = "rulebase") -> tuple[str, Path]:
    """(name, file) of a built-in name or a path; a name that is neither is an `InputError`."""
    text = str(spec)
    if text in builtin_names():
        return text, builtin_path(text)
    path = Path(text).expanduser()
    looks_like_path = path.suffix == ".toml" or "/" in text or "\\" in text or path.exists()
    if not looks_like_path:
        raise InputError(
            field,
            f"unknown rule base {text!r} "
            f"(built-in: {', '.join(builtin_names())}; or a path to a .toml file)",
        )
    if not path.exists():
        raise InputError(field, f"file not found: {text}")
    if not path.is_file():
        raise InputError(field, f"not a file: {text}")
    return path.stem, path.resolve()


def load_rulebase(spec: str | Path, field: str = "rulebase") -> RuleBase:
    """Load and validate a rule base from a built-in name or a TOML file path."""
    name, path = resolve(spec, field)
    stat = path.stat()
    return _load(name, str(path), stat.st_mtime_ns, stat.st_size, field)


@lru_cache(maxsize=32)
def _load(name: str, path: str, mtime_ns: int, size: int, field: str) -> RuleBase:
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except UnicodeDecodeError:
        raise InputError(field, f"{path} is not a UTF-8 text file (expected TOML)") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(field, f"{path} is not valid TOML: {exc}") from None
    except OSError as exc:
        raise InputError(field, f"cannot read {path}: {exc.strerror}") from None
    return rulebase_from_dict(data, name, where=f"{field} {Path(path).name}")
