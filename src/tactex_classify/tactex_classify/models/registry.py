# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The one registry of model names (and training bounds), importable without torch."""

# The original's eight deep models, in its table order: the one list of their names
# (tactex_classify.models.architectures defines a builder of each name).
ORIGINAL_MODELS = ('cnn_bilstm_1', 'cnn_bilstm_2', 'cnn_bilstm_3', 'cnn_1', 'cnn_2', 'cnn_3',
                   'bilstm_1', 'bilstm_2')
# Current architectures beside them (tactex_classify.models.modern_architectures).
MODERN_MODELS = ('inception_time', 'inception_time_ensemble', 'resnet', 'self_attention',
                 'cnn_attention')
DEEP_MODELS = ORIGINAL_MODELS + MODERN_MODELS
# Fast baselines (tactex_classify.models: baselines, multirocket, hydra).
BASELINES = ('minirocket', 'extratrees', 'multirocket', 'hydra', 'multirocket_hydra')
ALL_MODELS = DEEP_MODELS + BASELINES
# Augmentations of the deep models' `modern` training (tactex_classify.training.augmentation).
AUGMENTATIONS = ('shift', 'scale', 'jitter', 'warp', 'channel_dropout')
# Training profiles of the deep models (tactex_classify.training.deep_classifier.PROFILES).
PROFILE_NAMES = ('original', 'modern')
# Cross-validation schemes: grouped by recording (honest), stratified windows (leaky).
SCHEMES = ('grouped', 'stratified')
# Most epochs (and epochs of early-stopping patience) a training may be asked for.
MAX_EPOCHS = 100_000
