# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings to datasets, texture models, training, evaluation and the online classifier.

Subpackages by concern, each importing only from those above it in this list (the
workspace test holds it), each with its public names in `__all__`:
- `models`: the one registry of model names, the architectures, baselines, checkpoints;
- `data`: bags read into channels, stream alignment, datasets, imports, statistics;
- `recording`: the recorder node writing the bags `data` reads;
- `training`: the deep models' training loop, one constructor for every model;
- `online`: a checkpoint applied to a live stream, evidence, the classifier node;
- `evaluation`: cross-validation, the model grid, their reports;
- `identification`: per-movement evidence, the belief over textures across movements,
  the choice of the next movement, and its offline replay.
`errors` holds the exceptions all of them raise.
"""
