"""Fuzzy inference: rule bases as data, exact Mamdani inference, compiled lookup surfaces.

- `load_rulebase(name_or_path)`: a built-in (`deffao`, `classic`, `immune`) or a TOML file.
- `evaluate(rb, x)` / `evaluate_named(rb, {...})`: exact Mamdani min/max inference, centroid.
- `compiled(rb)` -> `CompiledSurface`: lookup surfaces, cached per rule base; `.table` goes to the
  compiled helpers `surface_lookup`, `surface_value` (and, inlined in kernels, `surface_output`)
  and to the fuzzy control laws in `chassistune.controllers`.

See docs/fuzzy.md.
"""

from chassistune.fuzzy.engine import evaluate, evaluate_named
from chassistune.fuzzy.loader import builtin_names, load_rulebase
from chassistune.fuzzy.rulebase import RuleBase, Variable
from chassistune.fuzzy.schema import rulebase_from_dict
from chassistune.fuzzy.sets import FuzzySet
from chassistune.fuzzy.surface import (
    CompiledSurface,
    SurfaceTable,
    compile_rulebase,
    compiled,
    surface_lookup,
    surface_value,
)

__all__ = [
    "CompiledSurface",
    "FuzzySet",
    "RuleBase",
    "SurfaceTable",
    "Variable",
    "builtin_names",
    "compile_rulebase",
    "compiled",
    "evaluate",
    "evaluate_named",
    "load_rulebase",
    "rulebase_from_dict",
    "surface_lookup",
    "surface_value",
]
