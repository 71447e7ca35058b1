# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Online use: a checkpoint applied to a live stream, evidence accumulated until confident.

- `runtime`: a checkpoint's predictor (native or onnxruntime), and ONNX export.
- `live`: windows from the live stream, classified (`OnlineClassifier`), without ROS.
- `evidence`: accumulated log-probabilities and the decision threshold.
- `stream_health`: clock jumps, an off rate, bad windows, judged without ROS.
- `classifier_node`: the ROS 2 node around them.
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'load_predictor': 'runtime', 'export_onnx': 'runtime',
            'OnlineClassifier': 'live', 'LiveSettings': 'live', 'Evidence': 'evidence',
            'EvidenceSettings': 'evidence', 'Timeline': 'stream_health',
            'RateJudge': 'stream_health'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
