# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bag-to-dataset conversion, texture models, training and the online classifier."""
