# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The report's three configurations, chosen among the live node's threshold rules."""

from __future__ import annotations

BUDGET_S = 2.0
NEAR_BEST = 0.05  # "fastest decision": within this much accuracy of the most accurate


def choose(points: list[dict], compute: list[dict]) -> dict:
    """The three configurations, among the live node's threshold rules (below 1: it decides).

    fastest: least contact time within `NEAR_BEST` accuracy of the most accurate;
    accurate: the most accurate (ties: less contact time); budget: the most accurate
    deciding within `BUDGET_S` of contact (None if none does). Each carries the runtime
    that answered a single window fastest in section 2 (`compute`). Models that did not
    converge are left out while any other is there.
    """
    live = [p for p in points if p['threshold'] is not None and p['threshold'] < 1.0]
    converged = [p for p in live if not p.get('not_converged')]
    live = converged or live  # a model that did not converge is chosen only if all did not
    accurate = max(live, key=lambda p: (p['accuracy'], -p['contact_s']))
    near = [p for p in live if p['accuracy'] >= accurate['accuracy'] - NEAR_BEST]
    fastest = min(near, key=lambda p: (p['contact_s'], -p['accuracy']))
    within = [p for p in live if p['contact_s'] <= BUDGET_S]
    budget = max(within, key=lambda p: (p['accuracy'], -p['contact_s'])) if within else None
    latency = {row['model']: row['latency'] for row in compute}

    def runtime(point: dict | None) -> dict | None:
        if point is None:
            return None
        timings = latency.get(point['model'], {})
        fastest_runtime = min(timings, key=lambda r: timings[r]['single_s'], default='native')
        return {**point, 'runtime': 'onnxruntime' if fastest_runtime == 'onnxruntime'
                else 'native'}
    return {'fastest': runtime(fastest), 'accurate': runtime(accurate),
            'budget': runtime(budget)}
