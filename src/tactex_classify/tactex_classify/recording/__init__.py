# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recording: the tactile topics into size- or time-split rosbag2 files (`recorder_node`).

Recording is data capture, not classification; it lives here because it writes the
format `tactex_classify.data.bags` reads, and it imports only from `data` below it.
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'SplitRecorder': 'recorder', 'RECORDED_TOPICS': 'recorder'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
