# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active identification: choose each next movement to tell the remaining textures apart.

The belief and the choice are pure numpy, apart from the ROS side (`movement_goals` and
`identify_node`, the `identify` action):
- `posterior`: the belief over textures in log space and its tempered update.
- `evidence_table`: what each movement's sweeps tell, from out-of-fold probability
  vectors per (true texture, movement), and the expected information gain of each.
- `selection`: the policies (active and its variants, random, fixed, round-robin) and one
  identification's loop state: next movement, update, threshold and budgets.
- `tempering`: the exponent and repeat discount that keep the independent-sweeps update honest.
- `calibration`: temperature scaling of a model's probabilities and its calibration error.
- `movement_evidence`: one model per movement, its calibrated out-of-fold sweep vectors.
- `offline`: every policy replayed on held-out recordings (nested, grouped folds).
- `report`: identification.json, identification.md and their plots.
- `pathway_part`: the part of a probed pathway one movement slides along.
- `movement_goals`: the Sweep goal of one movement on a probed pathway (ROS messages).
- `identify_node`: the node that runs the loop live, driving the sweep action.
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'EvidenceTable': 'evidence_table', 'MovementEvidence': 'evidence_table',
            'Identification': 'selection', 'Budget': 'selection', 'POLICIES': 'selection',
            'fit_tempering': 'tempering', 'fit_temperature': 'calibration',
            'reliability': 'calibration'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
