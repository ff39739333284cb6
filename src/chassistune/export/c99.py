"""C99 source of an exported discrete controller: controller.h and controller.c.

Each law's C (its `ct_step`, helpers and equations) is data of its module (`controllers.laws`,
`Law.c`); this module prints the parts every law shares around it. The C prints the arithmetic
of `chassistune.controllers.discrete` in the same operation order, so
that `cc -std=c99 -O2 -ffp-contract=off` (no FMA contraction) reproduces the numba law bit for
bit. Every number is printed with "%.17g", which reads back to the same double. The state is a
complete struct (`ct_state`, with the parameters in `ct_state.p`, tunable between steps); the
lookup tables are `static const` (read-only data: ROM on an ECU); no allocation, no mutable
globals, no library function at all (math.h only for the NAN macro).
"""

from __future__ import annotations

import re

import numpy as np
from numpy.typing import NDArray

from chassistune._version import __version__
from chassistune.controllers import discrete, laws
from chassistune.controllers.laws import CForm
from chassistune.export.source import ExportedController

HEADER = "controller.h"
SOURCE = "controller.c"
CHECK = "ct_check.c"
BITWISE_FLAGS = ("-std=c99", "-O2", "-ffp-contract=off")


def c_double(x: float) -> str:
    """A C double literal that reads back to exactly x ("%.17g", with a decimal point)."""
    x = float(x)
    if not np.isfinite(x):
        raise ValueError(f"cannot print {x!r} as a C constant")
    text = f"{x:.17g}"
    if not any(c in text for c in ".e"):
        text += ".0"
    assert float(text) == x
    return text


def c_name(name: str) -> str:
    """An upper-case C identifier fragment from a name (non-word characters become _)."""
    return re.sub(r"\W", "_", name).upper()


def _list(values: NDArray[np.float64], indent: str, per_line: int = 4) -> str:
    items = [c_double(v) for v in values]
    lines = [", ".join(items[i : i + per_line]) for i in range(0, len(items), per_line)]
    return "{ \\\n" + ",\\\n".join(indent + line for line in lines) + " }"


def _table_macro(table: NDArray[np.float64]) -> str:
    rows = [_list(row, "    ", 4).replace("\n", "\n  ") for row in table]
    return "{ \\\n  " + ", \\\n  ".join(rows) + " }"


_LOOKUP = """\
/* cell index and fraction of x on a uniform grid, clipped to it */
static int ct_locate(double lo, double step, int n, double x, double *f)
{
    double t = (x - lo) / step;
    int i;
    if (t < 0.0) t = 0.0;
    if (t > n - 1.0) t = n - 1.0;
    i = (int)t;
    if (i > n - 2) i = n - 2;
    *f = t - i;
    return i;
}

/* the cell of (x0, x1) in the tables' grid and the fractions in it; i = -1 for a NaN input */
typedef struct { int i, j; double f0, f1; } ct_cell;

static ct_cell ct_table_cell(double x0, double x1)
{
    ct_cell c;
    if (x0 != x0 || x1 != x1) {
        c.i = -1;
        c.j = 0;
        c.f0 = NAN;
        c.f1 = NAN;
        return c;
    }
    c.i = ct_locate(CT_TABLE_ROW_LO, CT_TABLE_ROW_STEP, CT_TABLE_ROWS, x0, &c.f0);
    c.j = ct_locate(CT_TABLE_COL_LO, CT_TABLE_COL_STEP, CT_TABLE_COLS, x1, &c.f1);
    return c;
}

/* bilinear interpolation of a table in a cell */
static double ct_lookup(const double tab[CT_TABLE_ROWS][CT_TABLE_COLS], ct_cell c)
{
    int i = c.i, j = c.j;
    if (i < 0) return NAN;
    return (tab[i][j] * (1.0 - c.f1) + tab[i][j + 1] * c.f1) * (1.0 - c.f0)
           + (tab[i + 1][j] * (1.0 - c.f1) + tab[i + 1][j + 1] * c.f1) * c.f0;
}
"""


def c_form(controller: str) -> CForm:
    """The C text of law `controller` (ValueError for a law without one)."""
    form = laws.get(controller).c
    if form is None:
        raise ValueError(f"law {controller!r} has no C form")
    return form


def header(ec: ExportedController) -> str:
    """The text of controller.h."""
    law = ec.law
    form = c_form(law.controller)
    sc = ec.scenario
    lines = [
        f"/* controller.h: {law.controller} ABS controller exported by chassistune {__version__}",
        " *",
        f" * Discrete form: {law.form}.",
        f" * Source: {ec.source}; plant {sc.plant}, preset {sc.preset}, road {sc.road}.",
        " * Call ct_init once, then ct_step once every CT_P_TS_S seconds with the inputs of",
        " * that sample (CT_INPUT_NAMES order); it returns the command u of the brake-pressure",
        " * modulator (dr/dt = (K u - r) / T, dq/dt = r in the plant model), to hold until the",
        " * next call. Parameters may be changed in ct_state.p between calls.",
        " *",
        " * Equations (e = target_slip - slip):",
        *(f" *   {line}" for line in form.equations),
        " *",
        " * Numbers are printed with %.17g: each reads back to the exact double.",
        " * Bit-exact build: cc " + " ".join(BITWISE_FLAGS) + " (no FMA contraction)",
        " * reproduces test_vectors.csv bit for bit."
        + (
            " Only that build is supported: with FMA contraction a"
            " rounding difference may switch a phase."
            if form.switching
            else " With FMA contraction the commands stay within 1e-9 (relative)."
        ),
        " */",
        "#ifndef CT_CONTROLLER_H",
        "#define CT_CONTROLLER_H",
        "",
        f"#define CT_N_INPUTS {len(law.inputs)}",
        "#define CT_INPUT_NAMES { " + ", ".join(f'"{n}"' for n in law.inputs) + " }",
    ]
    for i, name in enumerate(law.inputs):
        lines.append(f"#define CT_IN_{c_name(name)} {i} /* {discrete.INPUT_DESCRIPTIONS[name]} */")
    lines += ["", "/* exported parameter values (ct_init copies them into ct_state.p) */"]
    lines += [f"#define CT_P_{c_name(n)} {c_double(v)}" for n, v in ec.param_dict().items()]
    if law.table_outputs:
        lines += _table_lines(ec)
    lines += [
        "",
        "typedef struct {",
        *(f"    double {n};" for n in law.params),
        "} ct_params;",
        "",
        "typedef struct {",
        "    ct_params p; /* parameters, tunable between steps */",
        *(f"    double {n};" for n in law.state),
        "} ct_state;",
        "",
        "void ct_init(ct_state *s);",
        "double ct_step(ct_state *s, const double *inputs);",
        "",
        "#endif",
        "",
    ]
    return "\n".join(lines)


def _table_lines(ec: ExportedController) -> list[str]:
    rows, cols = ec.table_inputs
    bp_rows, bp_cols = ec.breakpoints
    lo0, step0, lo1, step1 = ec.grid.tolist()
    lines = [
        "",
        f"/* lookup tables of rule base {ec.rulebase!r}: CT_TABLE_<OUTPUT>[i][j] is the output",
        f" * at {rows} = CT_BP_{c_name(rows)}[i] (rows) and {cols} = CT_BP_{c_name(cols)}[j]"
        " (columns),",
        " * exact Mamdani inference at the nodes; read at the scaled inputs (ke e, kec de/dt),",
        " * clipped to the grid, by bilinear interpolation on the uniform grid lo + i step",
        " * (CT_TABLE_ROW_LO/STEP, CT_TABLE_COL_LO/STEP; the breakpoints are these nodes). */",
        f"#define CT_TABLE_ROWS {bp_rows.size}",
        f"#define CT_TABLE_COLS {bp_cols.size}",
        f"#define CT_TABLE_ROW_LO {c_double(lo0)}",
        f"#define CT_TABLE_ROW_STEP {c_double(step0)}",
        f"#define CT_TABLE_COL_LO {c_double(lo1)}",
        f"#define CT_TABLE_COL_STEP {c_double(step1)}",
        f"#define CT_BP_{c_name(rows)} " + _list(bp_rows, "    "),
        f"#define CT_BP_{c_name(cols)} " + _list(bp_cols, "    "),
    ]
    for k, out in enumerate(ec.table_outputs):
        lines.append(f"#define CT_TABLE_{c_name(out)} " + _table_macro(ec.table[k]))
    return lines


def source(ec: ExportedController) -> str:
    """The text of controller.c."""
    law = ec.law
    outs = [c_name(o).lower() for o in ec.table_outputs]
    parts = [
        f"/* controller.c: {law.controller} ABS controller exported by chassistune "
        f"{__version__} (see controller.h) */",
        '#include "controller.h"',
    ]
    if law.table_outputs:
        parts.append("#include <math.h> /* NAN only */\n")
        parts += [
            f"static const double ct_table_{o}[CT_TABLE_ROWS][CT_TABLE_COLS] = "
            f"CT_TABLE_{o.upper()};"
            for o in outs
        ]
        parts.append("\n" + _LOOKUP)
    else:
        parts.append("")
    form = c_form(law.controller)
    parts += form.helpers
    init = [f"    s->p.{n} = CT_P_{c_name(n)};" for n in law.params]
    init += [f"    s->{n} = 0.0;" for n in law.state]
    parts.append("void ct_init(ct_state *s)\n{\n" + "\n".join(init) + "\n}\n")
    step = form.step
    for k, o in enumerate(outs):
        step = step.replace("{" + str(k) + "}", o)
    parts.append(step)
    return "\n".join(parts)


CHECK_PROGRAM = """\
/* ct_check.c: replay test_vectors.csv through ct_step and compare bit for bit (==); with a
 * repeat count, also time ct_step over the rows (CPU time per call, C clock()).
 * Build and run on the target toolchain:
 *   cc -std=c99 -O2 -ffp-contract=off controller.c ct_check.c -o ct_check
 *   ./ct_check [test_vectors.csv [repeats]]
 * Exit status 0 when every command matches. Uses stdio and malloc (controller.c does not). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "controller.h"

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "test_vectors.csv";
    long repeats = argc > 2 ? atol(argv[2]) : 0;
    static char line[65536];
    double *rows = NULL, got, sink = 0.0;
    long n = 0, cap = 0, k, r, bad = 0;
    ct_state s;
    clock_t t0;
    FILE *f = fopen(path, "r");
    if (!f || !fgets(line, sizeof line, f)) {
        fprintf(stderr, "ct_check: cannot read %s\\n", path);
        return 2;
    }
    while (fgets(line, sizeof line, f)) {
        char *p = line;
        int j;
        if (n == cap) {
            cap = cap ? 2 * cap : 4096;
            rows = (double *)realloc(rows, (size_t)cap * (CT_N_INPUTS + 1) * sizeof(double));
            if (!rows) return 2;
        }
        for (j = 0; j <= CT_N_INPUTS; j++) {
            rows[n * (CT_N_INPUTS + 1) + j] = strtod(p, &p);
            p++; /* the comma */
        }
        n++;
    }
    fclose(f);
    ct_init(&s);
    for (k = 0; k < n; k++) {
        double *row = rows + k * (CT_N_INPUTS + 1);
        got = ct_step(&s, row);
        if (!(got == row[CT_N_INPUTS])) {
            if (bad < 10) {
                printf("row %ld: u = %.17g, expected %.17g\\n", k + 1, got, row[CT_N_INPUTS]);
            }
            bad++;
        }
    }
    printf("%ld rows, %ld mismatches\\n", n, bad);
    if (repeats > 0 && n > 0) {
        t0 = clock();
        for (r = 0; r < repeats; r++) {
            ct_init(&s);
            for (k = 0; k < n; k++) sink += ct_step(&s, rows + k * (CT_N_INPUTS + 1));
        }
        printf("%.1f ns per ct_step (%ld calls; checksum %g)\\n",
               1e9 * (double)(clock() - t0) / CLOCKS_PER_SEC / ((double)repeats * n),
               repeats * n, sink);
    }
    free(rows);
    return bad != 0 || n == 0;
}
"""
