"""cocopp's post-processing of COCO data folders: its ECDF figures, tables and HTML pages
(Hansen et al. 2021, COCO), built aside and moved in whole."""

from __future__ import annotations

import os
import tempfile
import warnings
from pathlib import Path

from chassistune.studies.coco_data import move_in

PP_FOLDER = "ppdata"


def postprocess(data_folders: list[Path], out: Path) -> Path:
    """`cocopp` over the data folders into `out` (ECDF figures, tables, index.html), built beside
    and moved in whole; the path of its index.html."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    with (
        tempfile.TemporaryDirectory(prefix="chassistune-cocopp-") as tmp,
        warnings.catch_warnings(record=True),
    ):
        # cocopp's warnings recorded, not shown (cocopp.main sets filters of its own): its notes
        # on partial data ("less than 15 instances") and on the online archive of reference
        # results, which it fetches and offline cannot reach (none is compared here)
        import cocopp

        cocopp.main(["--no-interactive", "-o", tmp, *(str(p) for p in data_folders)])
        move_in(Path(tmp), out)
    return out / "index.html"
