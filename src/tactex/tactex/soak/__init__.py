# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The soak test: `bookkeeping` (fault schedule, window ledger, memory; no ROS) and `session`.

`bench/soak.py` runs it: the demo's launched system for minutes with a fault injected
every period, judged by `session`'s client and accounted for by `bookkeeping`.
"""
