"""The transfer study (docs/transfer.md): the papers' tuned ABS controllers, taken from a
reproduction's stores, run unchanged on the real cars (with the Magic Formula tire, the lagged
slip and the realistic ECU where the kernels have them), then re-tuned on each car. `cells`
declares the sources, targets and variants; `plan` the re-tuning studies; `score` the table's
rows (scored by the league's code); `page` the table and figures."""
