# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What accuracy costs in time: `tactex report accuracy-time`, every number measured in its run.

`report.write_report(folder, size)` runs the seven sections (`classification`: contact
time and compute time; `physical`: probing, sweep speed, simulation cost, filter rate;
`pipeline`: the whole job end to end) and writes report.md with its PNG plots.
"""
