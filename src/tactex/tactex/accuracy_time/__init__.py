# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What accuracy costs in time: `tactex report accuracy-time`, every number measured in its run.

`report.write_report(folder, size)` runs the seven sections of `sections.SECTIONS` (each
row: number, title, plot file, how to measure, plot and render it; the measurements in
`classification`, `physical`, `sweep_speed` and `pipeline`, the plots in `plots`, the
text in `section_text`), picks the three configurations (`configurations`) and writes
report.md (`markdown`) with its PNG plots and results.json. Imports run one way:
report -> markdown -> sections -> the rest.
"""
