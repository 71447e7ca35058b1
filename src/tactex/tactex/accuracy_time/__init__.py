# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What accuracy costs in time: `tactex report accuracy-time`, every number measured in its run.

`runner.write_report(folder, size)` runs the eight sections of `sections.SECTIONS` (each
row: number, title, plot file, how to measure, plot and render it; the measurements in
`classification`, `physical`, `sweep_speed` and `whole_job`, the plots in `plots`, the
text in `section_text`), picks the three configurations (`configurations`) and writes
report.md (`markdown`) with its PNG plots and results.json. Imports run one way:
runner -> markdown -> sections -> the rest.
"""
